"""Robot model: joints, the immutable :class:`Robot`, and robot files."""

from .files import bundled_robots, dumps, load, save
from .robot import Chain, Joint, Link, Robot, Shape

__all__ = ["Joint", "Robot", "Chain", "Link", "Shape", "load", "save", "dumps", "bundled_robots"]
