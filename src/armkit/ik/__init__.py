"""Inverse kinematics: closed form with every branch, LM/Newton, CCD and FABRIK, honest results.

:func:`ik` returns one solution per target, :func:`ik_all` every closed-form branch; both
return an :class:`IKResult` whose ``success`` was checked by forward kinematics.
"""

from .api import IKInputError, closed_form_family, ik, ik_all   # IKInputError lives in armkit.errors
from .result import IKResult, default_tolerance, verify

__all__ = ["IKResult", "default_tolerance", "verify", "ik", "ik_all", "IKInputError", "closed_form_family"]
