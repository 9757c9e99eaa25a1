"""Fixtures shared by the CLI tests (the resonance dataset ``small_dataset`` is in tests/conftest.py,
shared with tests/robustness)."""
