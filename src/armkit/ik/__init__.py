"""Inverse kinematics: closed form with every branch, LM/Newton, CCD and FABRIK, honest results."""

from .result import IKResult, default_tolerance, verify

__all__ = ["IKResult", "default_tolerance", "verify"]
