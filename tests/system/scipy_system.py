"""The independent scipy reference of the system core, :func:`contactvib.testing.integrate_system`
(``solve_ivp`` DOP853 mode by mode, a terminal event on every contact's switch), re-exported for
the tests of ``tests/system``."""

from contactvib.testing import integrate_system

__all__ = ["integrate_system"]
