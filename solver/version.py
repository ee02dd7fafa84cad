"""The package version (one place; ``solver.__version__``)."""

__version__ = "0.1.0"
