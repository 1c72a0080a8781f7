"""The package's version, in one place (read by the package, the database metadata and setup)."""

__version__ = "0.1.0"
