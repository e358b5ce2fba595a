"""The runs layer: training a behaviour into a run directory
(:mod:`~locustjump.runs.trainer`) and reproducing the paper, for one seed or
many (:mod:`~locustjump.runs.reproduce`, :mod:`~locustjump.runs.multiseed`)."""
