"""Reports: the scenario-run report (:mod:`.scenario`) with its figures, tables and CSV logs."""
