"""Re-runs of the papers' experiments on the models (an upper layer: uses models and sim).

* :mod:`ecoplan.experiments.ab_replay` -- the A->B obstacle experiment of the tracked paper
  (§IV-A, Table III, Fig. 14), with the sensitivity of its findings to the non-regenerated
  power's onset.
"""
