"""Reading and writing files: YAML documents with line numbers, logs, datasets, maps."""
