"""The version of balance (one place, read by the build and by the output files)."""

__version__ = "0.1.0"
