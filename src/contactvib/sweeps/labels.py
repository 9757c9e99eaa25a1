"""Resonance labels of attractors and how to read them back.

A label (:func:`contactvib.sweeps.dataset.resonance_label`) is ``"main"``, ``"1/m"``, ``"main
period-k"``, ``"1/m period-k"``, ``"non-periodic (1/m)"``, ``"non-resonant"``,
``"subharmonic 1/q"`` or ``"ultrasubharmonic p/q"`` (with ``" bouncing"``). This module is the one
place that parses them.
"""

from __future__ import annotations

__all__ = ["resonance_order", "label_family", "period_one_order"]


def resonance_order(label) -> int | None:
    """Order m of the resonance a label belongs to: ``"main…"`` → 1, ``"1/m …"`` → m,
    ``"non-periodic (1/m)"`` → m; None for non-resonant and sub-/ultrasubharmonic labels."""
    m, _variant = label_family(label)
    return m


def label_family(label) -> tuple[int | None, str]:
    """(order m or None, variant) of a label: ``"1/3 period-2"`` → (3, "period-2"),
    ``"main"`` → (1, ""), ``"non-periodic (1/5)"`` → (5, "non-periodic"),
    ``"subharmonic 1/2"`` → (None, "subharmonic 1/2")."""
    label = str(label)
    if label.startswith("non-periodic ("):
        m, _ = label_family(label[len("non-periodic ("):-1])
        return m, "non-periodic"
    if label.startswith("main"):
        return 1, label[4:].strip()
    if label.startswith("1/"):
        head, _, rest = label.partition(" ")
        if head[2:].isdigit():
            return int(head[2:]), rest
    return None, label


def period_one_order(label) -> int | None:
    """m of a period-1 resonance label, exactly ``"main"`` (1) or ``"1/m"`` (m); else None."""
    m, variant = label_family(label)
    return m if variant == "" else None
