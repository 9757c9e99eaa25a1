"""The one calling rule of the public verbs, and their old call forms kept for one release.

The rule (ARCHITECTURE.md, "How to add an analysis"): the first argument says *where*. A verb
at one operating point takes the :class:`~contactvib.Excitation` (which carries its model:
``excitation.model``); a verb over a range of levels or frequencies takes the
:class:`~contactvib.ContactModel` and its levels by keyword (``pa_over_q=``, ``fe_hz=``,
``levels=``; ranges and tolerances in its settings object). What the verb acts on (an attractor,
a state, a special point, a dataset) follows positionally; every option is keyword-only.

:func:`old_form` decorates a verb with the parameter names of its previous signature: a call
that fits only that one (the model before the excitation, options given positionally, a renamed
keyword) still runs, the same computation, with a :class:`DeprecationWarning` that names the new
form. The old forms are removed in the release after 0.2.0.
"""

from __future__ import annotations

import functools
import inspect
import warnings

__all__ = ["old_form", "new_form_text", "renamed_fields"]

_POSITIONAL = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)


def new_form_text(fn) -> str:
    """The verb's call form, its positional names then ``*, option=...`` (for the warning)."""
    params = inspect.signature(fn).parameters.values()
    pos = [p.name for p in params if p.kind in _POSITIONAL]
    kw = [p.name for p in params if p.kind == inspect.Parameter.KEYWORD_ONLY]
    return f"{fn.__name__}({', '.join(pos + (['*'] if kw else []) + [f'{k}=...' for k in kw[:3]])}" \
           f"{', ...' if len(kw) > 3 else ''})"


def _first_is_new(first: str, value, strict: bool = False) -> bool:
    """Whether ``value`` fits the new first parameter (an Excitation, or a model or None); not
    ``strict``: anything but a model may be an excitation, for the new form to check."""
    from contactvib.model.excitation import Excitation
    from contactvib.model.oscillator import ContactModel

    if first == "excitation":
        return isinstance(value, Excitation) if strict else not isinstance(value, ContactModel)
    if first == "model":
        return isinstance(value, ContactModel) or (value is None and not strict)
    return True


def _is_old(fn_params, positional, old, renamed, args, kwargs) -> bool:
    if len(args) > len(positional) or any(k in renamed for k in kwargs):
        return True
    if any(k not in fn_params and k in old for k in kwargs):  # e.g. model= of a point verb
        return True
    return bool(args) and old[0] != positional[0] and not _first_is_new(positional[0], args[0])


def _drop_model(bound: dict) -> None:
    """The old forms' ``model`` before the excitation: it must be the excitation's own."""
    from contactvib.model.excitation import check_excitation

    check_excitation(bound.get("excitation"), bound.pop("model"))


def old_form(*old: str, renamed: dict | None = None):
    """Keep the old call form ``name(*old)`` of a verb working, with a DeprecationWarning.

    Parameters
    ----------
    *old : str
        The previous signature's parameter names in order (positional options included).
    renamed : dict, optional
        Old keyword -> new keyword.

    Examples
    --------
    >>> import warnings
    >>> from contactvib import ContactModel, perturbation_series
    >>> exc = ContactModel().excitation(0.3, 600.0)
    >>> new = perturbation_series(exc, terms=8)               # the operating point, then keywords
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     old = perturbation_series(exc.model, exc, 8)      # the form of 0.1
    >>> old.app_um == new.app_um, caught[0].category.__name__
    (True, 'DeprecationWarning')
    """
    renamed = dict(renamed or {})

    def decorate(fn):
        params = inspect.signature(fn).parameters
        positional = [n for n, p in params.items() if p.kind in _POSITIONAL]

        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            if not _is_old(params, positional, old, renamed, args, kwargs):
                return fn(*args, **kwargs)
            if len(args) > len(positional) and old[0] != positional[0] and _first_is_new(positional[0], args[0],
                                                                                        strict=True):
                raise TypeError(f"{fn.__name__}() takes {len(positional)} positional argument(s); its options "
                                f"are keyword-only: {new_form_text(fn)}")
            if len(args) > len(old):
                raise TypeError(f"{fn.__name__}() takes at most {len(old)} positional arguments "
                                f"({len(args)} given)")
            bound = dict(zip(old, args))
            for k, v in kwargs.items():
                k = renamed.get(k, k)
                if k in bound:
                    raise TypeError(f"{fn.__name__}() got multiple values for argument {k!r}")
                bound[k] = v
            bound = {renamed.get(k, k): v for k, v in bound.items()}
            warnings.warn(f"this call form of {fn.__name__} is deprecated (removed after 0.2.0): call "
                          f"{new_form_text(fn)}", DeprecationWarning, stacklevel=2)
            if "model" in bound and "model" not in params:
                _drop_model(bound)
            return fn(**bound)

        return wrapper

    return decorate


def renamed_fields(**old_to_new: str):
    """Class decorator of a settings dataclass: its renamed fields (old name = new name) stay
    accepted by the constructor (and :func:`dataclasses.replace`) and readable as attributes, with
    a DeprecationWarning naming the new field."""

    def decorate(cls):
        init = cls.__init__

        def warn(old):
            warnings.warn(f"{cls.__name__}.{old} is deprecated (removed after 0.2.0): use "
                          f"{cls.__name__}.{old_to_new[old]}", DeprecationWarning, stacklevel=3)

        @functools.wraps(init)
        def __init__(self, *args, **kwargs):
            for old in [k for k in kwargs if k in old_to_new]:
                warn(old)
                kwargs[old_to_new[old]] = kwargs.pop(old)  # over the new name: dataclasses.replace gives both
            init(self, *args, **kwargs)

        def __getattr__(self, name):  # only names that are not attributes reach here
            if name in old_to_new:
                warn(name)
                return getattr(self, old_to_new[name])
            raise AttributeError(f"{cls.__name__!r} object has no attribute {name!r}")

        cls.__init__, cls.__getattr__ = __init__, __getattr__
        return cls

    return decorate
