"""`make derive`: regenerate generated/ from the model definitions (python -m derive)."""
