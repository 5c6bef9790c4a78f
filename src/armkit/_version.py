"""armkit's version (the ground floor: ``armkit.__version__`` and what a reachability map records)."""

__version__ = "0.1.0"
