"""Pages written when the documentation is built (called from ``docs/conf.py``).

- ``api/generated/<topic>.rst``: one page per topic of :data:`API_TOPICS`, one autodoc entry per
  name of the public packages' ``__all__`` on the page of the subpackage that defines it, so a new
  public name appears by itself and a removed one disappears;
- ``generated/paper_statements.md``: the paper's statements S2.1–S4.7, where ``contactvib paper``
  shows each and which tests and modules name it;
- ``benchmarks.md``: one table per committed ``benchmarks/results_*.json``, flattened to
  (quantity, value) rows — the current numbers, not a dated log.
"""

from __future__ import annotations

import importlib
import inspect
import json
from pathlib import Path

#: the public packages, in the order of the API reference; a name documented under an earlier
#: package (``contactvib`` first) is only listed under a later one
API_PACKAGES = ("contactvib", "contactvib.model", "contactvib.plotting", "contactvib.fitting",
                "contactvib.friction", "contactvib.cli", "contactvib.testing")


#: the topics of the API reference, in its order: (page, title, what the page holds). Each public
#: name is on the page of the subpackage that defines it (:func:`topic_of`).
API_TOPICS = (
    ("model", "The model: contact laws, excitations, units",
     "The oscillator and its parameters (`ContactModel`), the excitations, the contact laws as objects, "
     "the units and the input checks that every command and function shares."),
    ("steady", "Steady states, attractors and basins",
     "Every coexisting attractor at one operating point, its time history, Newton-refined orbits and "
     "basins of attraction."),
    ("continuation", "Continuation and bifurcations",
     "Pseudo-arclength continuation of periodic orbits in f_e or P_a, special points, branch "
     "switching, two-parameter fold and period-doubling curves."),
    ("frequency", "Perturbation series and harmonic balance",
     "The frequency-domain methods: the perturbation series in P_a/Q and harmonic balance with its "
     "continuation."),
    ("sweeps", "Resonance sweeps, datasets and the paper",
     "Resonance graphs over many levels and frequencies, the datasets they write and read, the "
     "reproduction of the paper, the film and the regime maps."),
    ("friction", "Friction under normal vibration",
     "The tangential motion of the slider driven along the slideway while the normal contact vibrates."),
    ("fitting", "Fitting a contact to measurements",
     "Least-squares fits of the contact parameters to static, free-decay and stepped-sine data."),
    ("plotting", "Plotting",
     "The figures of the command line as functions (matplotlib)."),
    ("errors", "Errors",
     "The base class of the package's errors and the one error of a computation that fails, "
     "`ComputationError`, whose `stage` says where (Newton shooting, continuation, harmonic balance, "
     "friction, a fit, ...). Bad input raises `ParameterError` (model) or `DatasetError` (sweeps) before "
     "any computation."),
    ("testing", "Reference solver",
     "The reference the tests check the kernels against: the contact oscillator in scipy's `solve_ivp`, "
     "mode by mode with located contact events, written independently of the compiled kernels."),
    ("cli", "Command-line entry point",
     "The click group behind the `contactvib` command and its console-script entry point; every "
     "command and option is in the command-line reference."),
)
_TOPIC_SLUGS = tuple(t[0] for t in API_TOPICS)


def _directive(module: str, name: str, obj) -> str:
    if inspect.isclass(obj):
        return f".. autoclass:: {module}.{name}\n   :members:\n"
    if callable(obj):
        return f".. autofunction:: {module}.{name}\n"
    return f".. autodata:: {module}.{name}\n   :no-value:\n"


def api_entries() -> dict[str, list[tuple[str, str | None]]]:
    """package -> [(name, None) for names documented there, (name, home) for names documented
    under an earlier package ``home``]."""
    seen: dict[int, str] = {}
    out: dict[str, list[tuple[str, str | None]]] = {}
    for package in API_PACKAGES:
        mod = importlib.import_module(package)
        rows = []
        for name in mod.__all__:
            if name.startswith("__"):
                continue
            obj = getattr(mod, name)
            key = id(obj) if (inspect.isclass(obj) or callable(obj)) else id((package, name))
            rows.append((name, seen.get(key)))
            seen.setdefault(key, package)
        out[package] = rows
    return out


def topic_of(package: str, name: str) -> str:
    """The API page of ``package.name``: the subpackage that defines it (``contactvib.steady.…`` →
    ``steady``), that of ``package`` for a subpackage's data, ``model`` for the top level's data."""
    obj = getattr(importlib.import_module(package), name)
    where = getattr(obj, "__module__", None) if (inspect.isclass(obj) or callable(obj)) else None
    parts = (where or package).split(".")
    part = parts[1] if len(parts) > 1 else "model"
    if part not in _TOPIC_SLUGS:
        raise ValueError(f"{package}.{name} (module {where}): no API topic for {part!r}; add it to API_TOPICS")
    return part


def api_topics() -> dict[str, list[tuple[str, list[str], list[tuple[str, str]]]]]:
    """topic -> [(package, names documented on the topic's page, [(name, home)] of the package's
    names documented under an earlier package)] for the packages with a name on the page."""
    out: dict[str, dict[str, tuple[list[str], list[tuple[str, str]]]]] = {t: {} for t in _TOPIC_SLUGS}
    for package, rows in api_entries().items():
        for name, home in rows:
            topic = topic_of(home or package, name)
            own, again = out[topic].setdefault(package, ([], []))
            (own.append(name) if home is None else again.append((name, home)))
    return {t: [(p, own, again) for p, (own, again) in packages.items()] for t, packages in out.items()}


def api_rst(topic: str, sections) -> str:
    slug, title, summary = next(t for t in API_TOPICS if t[0] == topic)
    lines = [title, "=" * len(title), "", summary.replace("`", "``"), ""]
    for package, own, again in sections:
        mod = importlib.import_module(package)
        head = f"From ``{package}``"
        lines += [head, "-" * len(head), "", f".. currentmodule:: {package}", ""]
        if again:
            lines += ["Also importable from ``" + package + "``: "
                      + ", ".join(f":py:obj:`{n} <{home}.{n}>`" for n, home in again) + ".", ""]
        lines += [_directive(package, name, getattr(mod, name)) for name in own]
    return "\n".join(lines) + "\n"


def write_api_pages(folder: Path) -> list[Path]:
    """``folder/generated/<topic>.rst``, one page per entry of :data:`API_TOPICS`."""
    gen = folder / "generated"
    gen.mkdir(parents=True, exist_ok=True)
    written = []
    for topic, sections in api_topics().items():
        path = gen / f"{topic}.rst"
        text = api_rst(topic, sections)
        if not path.is_file() or path.read_text() != text:  # unchanged pages keep Sphinx's cache
            path.write_text(text)
        written.append(path)
    for stale in set(gen.glob("*.rst")) - set(written):
        stale.unlink()
    return written


def _flatten(value, prefix: str = ""):
    """(dotted key, value) rows of a JSON value; lists of numbers or strings stay one row."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _flatten(v, f"{prefix}.{k}" if prefix else str(k))
    elif isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
        for i, v in enumerate(value):
            yield from _flatten(v, f"{prefix}[{i}]")
    else:
        yield prefix, value


def _cell(value) -> str:
    if isinstance(value, list):
        text = ", ".join(_cell(v) for v in value[:12]) + (f", … ({len(value)} values)" if len(value) > 12 else "")
    elif isinstance(value, float):
        text = f"{value:.6g}"
    else:
        text = str(value)
    return text.replace("|", "\\|").replace("\n", " ")


def benchmarks_markdown(folder: Path) -> str:
    files = sorted(folder.glob("results_*.json"))
    out = ["# Benchmarks", "",
           "How long the main computations take and how they compare with a general-purpose "
           "integrator. The numbers are read, when this page is built, from the measurement files "
           "kept in the repository's `benchmarks/` folder (one table per measurement; nested keys "
           "are joined with dots); the machine and its load are in the table where they were "
           "recorded.", "",
           (Path(__file__).parent / "benchmarks_intro.md").read_text(), ""]
    for f in files:
        name = f.stem.removeprefix("results_")
        out += [f"## `{name}`", "", f"From `benchmarks/{f.name}` (`python -m benchmarks {name}`).", "",
                "| quantity | value |", "|---|---|"]
        out += [f"| `{k}` | {_cell(v)} |" for k, v in _flatten(json.loads(f.read_text()))]
        out.append("")
    return "\n".join(out)


def _write_if_changed(page: Path, text: str) -> Path:
    """Write a build-time page only when its text changed (Sphinx rebuilds what changed)."""
    page.parent.mkdir(parents=True, exist_ok=True)
    if not page.is_file() or page.read_text() != text:
        page.write_text(text)
    return page


def write_benchmarks_page(folder: Path, page: Path) -> Path:
    return _write_if_changed(page, benchmarks_markdown(folder))


def statements(path: Path) -> dict[str, str]:
    """The paper's statements by id (``"S3.2"`` → text) from ``data/paper_statements.md``."""
    out: dict[str, str] = {}
    current = None
    for line in path.read_text().splitlines():
        if line.startswith("- S"):
            current, text = line[2:].split(" ", 1)
            out[current] = text
        elif current and line.startswith("  ") and line.strip():
            out[current] += " " + line.strip()
        else:
            current = None
    return out


def _where_shown(sid: str, text: str) -> str:
    """Where ``contactvib paper`` shows statement ``sid``: ``index.md`` always, and the figures
    of its level (S3) or its figure number (S4)."""
    import re

    if sid.startswith("S4."):
        m = re.match(r"\(Fig\. (\d+)", text)
        return f"`fig{m.group(1)}_*.png`, `index.md`" if m else "`index.md`"
    if sid in ("S3.8", "S3.9"):
        return "`fig2*.png`, `fig3*.png` (all levels), `index.md`"
    if sid.startswith("S3."):
        return "`fig2*`/`fig3*` of the level(s) named, `index.md`"
    return "`index.md` (model line)"


def statements_markdown(src: Path, tests: Path) -> str:
    """A table of the paper's statements S2.1–S4.7, where ``contactvib paper`` shows each and
    which test files and modules name it (found by searching the sources for its id)."""
    files = sorted([*tests.rglob("*.py"), *src.rglob("*.py")])
    texts = {f: f.read_text(encoding="utf-8") for f in files}
    rows = ["| id | the paper says | shown in `paper/` | named by |", "|---|---|---|---|"]
    for sid, text in statements(src / "data" / "paper_statements.md").items():
        named = [f.relative_to(src.parents[1]).as_posix() for f in files if sid in texts[f]]
        cell = ", ".join(f"`{n}`" for n in named) or "—"
        rows.append(f"| {sid} | {_cell(text)} | {_where_shown(sid, text)} | {cell} |")
    return "\n".join(rows) + "\n"


def write_statements_page(root: Path, page: Path) -> Path:
    return _write_if_changed(page, statements_markdown(root / "src" / "contactvib", root / "tests"))


def dataset_variables_markdown() -> str:
    """The variables of a resonance dataset (``paper.nc``, ``resonance.nc``, ``atlas.nc``) with
    their dimensions, type, units and description, read from a small dataset computed here (one
    level, three frequencies), so the table is the one the code writes."""
    from contactvib import ContactModel, SweepSettings, resonance_dataset

    settings = SweepSettings(fmin_hz=355.0, fmax_hz=365.0, df_hz=5.0, multistart_per_octave=0)
    ds = resonance_dataset(ContactModel(), levels=[0.65], settings=settings, workers=1, progress=False)
    rows = ["| variable | dimensions | type | units | description |", "|---|---|---|---|---|"]
    for name, var in ds.variables.items():
        text = " ".join(str(var.attrs[k]) for k in ("long_name", "comment") if k in var.attrs)
        rows.append(f"| `{name}` | {', '.join(var.dims)} | {var.dtype} | {_cell(var.attrs.get('units', ''))} "
                    f"| {_cell(text)} |")
    rows += ["", "Attributes of the dataset: " + ", ".join(f"`{k}`" for k in ds.attrs) + "."]
    return "\n".join(rows) + "\n"


def write_dataset_page(page: Path) -> Path:
    return _write_if_changed(page, dataset_variables_markdown())


def laws_markdown() -> str:
    """The table of the registered contact laws (the registry's, plug-ins included): name,
    formula, parameters with unit, default and bounds, and the fast paths each one takes."""
    from contactvib.model.laws import law_class, law_names

    rows = ["| `--law` | force | parameters (`--set`) | Taylor flow | harmonic balance |", "|---|---|---|---|---|"]
    for name in law_names():
        cls = law_class(name)
        params = "; ".join(f"`{p.name}` [{_cell(p.unit)}] {_cell(p.description)}, default {p.default:g}, "
                           f"{_cell(p.bounds_text())}" for p in cls.parameters)
        if name == "table":
            params = "`--law-file FILE.csv` (deflection_um, load_n)"
        rows.append(f"| `{name}` | {_cell(cls.formula)} | {params or '(none)'} | {'yes' if cls.taylor else 'no'} "
                    f"| {'yes' if cls.fourier else 'no'} |")
    return "\n".join(rows) + "\n"


def write_laws_page(page: Path) -> Path:
    return _write_if_changed(page, laws_markdown())
