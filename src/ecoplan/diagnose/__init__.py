"""Sim-to-real gap diagnosis: where a model departs from logs, which effect is missing, how far.

Modules, in the order of the pipeline:

* the log (:class:`ecoplan.dynamics.log.Log`) comes from :mod:`ecoplan.io` (CSV, BorealTC,
  ROS 2 bags: :func:`ecoplan.io.logs.read_logs`);
* :mod:`ecoplan.diagnose.replay` -- the model replayed on the logged inputs, residuals;
* :mod:`ecoplan.diagnose.calibrate` -- the preset's own parameters re-identified first;
* :mod:`ecoplan.diagnose.localise` -- where the gap lies (regimes, time, space);
* :mod:`ecoplan.diagnose.effects` -- the library of candidate unmodelled effects;
* :mod:`ecoplan.diagnose.attribute` -- held-out ranking, significance, verdict;
* :mod:`ecoplan.diagnose.pipeline` -- :func:`~ecoplan.diagnose.pipeline.diagnose` and the CLI
  back end;
* :mod:`ecoplan.diagnose.result` -- :class:`~ecoplan.diagnose.result.Diagnosis`, what it returns;
* :mod:`ecoplan.diagnose.loop` -- the corrected model as a file, route ranking under it;
* :mod:`ecoplan.diagnose.report` -- text summary, figures, JSON.

The blind check's generator of realistic logs with withheld effects is :mod:`ecoplan.synth`.
"""
