"""The emulated Dynamixel bus: Protocol 2.0 servos on a pseudo-terminal.

``from hand_driver.sim.server import EmulatedBus`` (faults: ``hand_driver.sim.faults``).
"""
