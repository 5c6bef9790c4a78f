"""Inverse kinematics: closed form with every branch, LM/Newton, CCD and FABRIK, honest results.

:func:`ik` returns one solution per target, :func:`ik_all` every closed-form branch; both
return an :class:`IKResult` whose ``success`` was checked by forward kinematics.
"""

from .api import IKInputError, closed_form_family, ik, ik_all   # IKInputError lives in armkit.errors
from .result import (DEFAULT_MAX_ITERATIONS, DEFAULT_MAX_SWEEPS, DEFAULT_NEWTON_RESTARTS, DEFAULT_RESTARTS,
                     DEFAULT_SWEEP_RESTARTS, DEFAULT_TOLERANCE, IKResult, default_tolerance, verify)

__all__ = ["IKResult", "default_tolerance", "verify", "ik", "ik_all", "IKInputError", "closed_form_family",
           "DEFAULT_TOLERANCE", "DEFAULT_MAX_ITERATIONS", "DEFAULT_RESTARTS", "DEFAULT_NEWTON_RESTARTS",
           "DEFAULT_MAX_SWEEPS", "DEFAULT_SWEEP_RESTARTS"]
