"""Walks generated for any robot model with two legs (``rcb4hv gait``, docs/gait.md).

* :mod:`~rcb4hv.gait.preview`: ZMP preview control of the linear inverted pendulum;
* :mod:`~rcb4hv.gait.pattern`: footsteps, the ZMP reference, CoM and swing-foot paths;
* :mod:`~rcb4hv.gait.generate`: the walk through the one IK into joint angles;
* :mod:`~rcb4hv.gait.motion`: the walk as a HeartToHeart4 motion in a project;
* :mod:`~rcb4hv.gait.tune`: CMA-ES over the gait parameters against fall probability.

NumPy is needed (the ``[gait]`` extra; MuJoCo's ``[sim]`` brings it too).
"""
