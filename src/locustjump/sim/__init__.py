"""The simulation layer: the creature and its world (one MJCF), sensors,
controllers, and the engine that steps a population of episodes at once
(:mod:`locustjump.sim.engine`). Imports nothing else of locustjump but
:mod:`locustjump.errors`."""
