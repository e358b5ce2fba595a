"""The rollout engine: every controller from every start state, batched
(:func:`~locustjump.sim.engine.rollout.rollout`): one control loop, its
strategies by name (:mod:`~locustjump.sim.engine.strategies`: NumPy, compiled,
in MuJoCo's callback), the one-``MjData`` reference loop, and the backends
that run a job (threads, Ray)."""
