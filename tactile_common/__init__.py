"""What the recognizer and the hand driver both need: the error types a person acts on
and the one YAML reader. Depends on nothing else of the project."""
