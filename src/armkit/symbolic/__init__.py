"""Symbolic kinematics with SymPy: derivation, short-hand, LaTeX and NumPy code export, 2R IK.

This package imports SymPy; ``import armkit`` never imports it (load it with
``import armkit.symbolic`` or ``from armkit.symbolic import derive``).
"""

from __future__ import annotations

from .._extras import require

require("sympy", "armkit.symbolic")
from .derive import (Derivation, cache_dir, derive, exact_angle, link_transform,  # noqa: E402 - after the check
                     simplify_entry)

__all__ = ["Derivation", "derive", "link_transform", "exact_angle", "simplify_entry", "cache_dir"]
