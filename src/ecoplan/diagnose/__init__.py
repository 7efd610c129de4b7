"""Sim-to-real gap diagnosis: where a model departs from logs, which effect is missing, how far.

Modules, in the order of the pipeline:

* the log (:class:`ecoplan.dynamics.log.Log`) comes from :mod:`ecoplan.io` (CSV, BorealTC,
  ROS 2 bags: :func:`ecoplan.io.logs.read_logs`);
* :mod:`ecoplan.diagnose.checks` -- units and excitation checked before anything is explained;
* :mod:`ecoplan.diagnose.replay` -- the model replayed on the logged inputs, residuals;
* :mod:`ecoplan.diagnose.calibrate` -- the preset's own parameters re-identified first;
* :mod:`ecoplan.diagnose.localise` -- where the gap lies (regimes, time, space);
  :mod:`ecoplan.diagnose.where_time` -- where on each log's own clock;
* :mod:`ecoplan.diagnose.effects` -- the library of candidate unmodelled effects;
* :mod:`ecoplan.diagnose.attribute` -- held-out ranking, significance, verdict;
  :mod:`ecoplan.diagnose.stats` -- noise floors, prewhitening, Ljung-Box, block bootstrap;
* :mod:`ecoplan.diagnose.pipeline` -- :func:`~ecoplan.diagnose.pipeline.diagnose`, the steps
  above in order;
* :mod:`ecoplan.diagnose.result` -- :class:`~ecoplan.diagnose.result.Diagnosis`, what it returns;
* :mod:`ecoplan.diagnose.corrected` -- the corrected model; :mod:`ecoplan.diagnose.ranking` --
  whether it changes which route is cheapest;
  :mod:`ecoplan.diagnose.corrected_file` -- its file (format tag, schema, reader);
* :mod:`ecoplan.diagnose.report` -- text summary, figures, JSON (and its schema);
  :mod:`ecoplan.diagnose.report_md` -- ``report.md``.

The command ``ecoplan diagnose`` (files in, report folder out) is :mod:`ecoplan.app.diagnose`.
The blind check's generator of realistic logs with withheld effects is :mod:`ecoplan.synth`.
"""
