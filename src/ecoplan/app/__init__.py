"""The application layer: scenario files, running them, output folders, reports, benches."""
