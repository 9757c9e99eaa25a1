"""``python -m benchmarks [NAME ...] [ARGS ...]``: list the benchmarks, or run the named ones.

Without a name: the list (name, result file, what it measures). ``all`` runs every benchmark
with its defaults. Arguments from the first one that starts with ``-`` on go to each named
benchmark's own options, e.g. ``python -m benchmarks atlas --levels 4`` or
``python -m benchmarks attractors --quick``; ``python -m benchmarks NAME --help`` shows them.
"""

from __future__ import annotations

import sys

from benchmarks import load, names, result_path, summary


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    split = next((i for i, a in enumerate(argv) if a.startswith("-")), len(argv))
    chosen, args = argv[:split], argv[split:]
    known = names()
    if not chosen:
        if args and args[0] not in ("-l", "--list", "-h", "--help"):
            print("python -m benchmarks: name a benchmark before its options", file=sys.stderr)
            return 2
        print("benchmarks (python -m benchmarks NAME [NAME ...] [ARGS ...]; 'all' runs every one):")
        for name in known:
            print(f"  {name:20s} {result_path(name).name:32s} {summary(name)}")
        return 0
    if chosen == ["all"]:
        chosen = known
    unknown = [n for n in chosen if n not in known]
    if unknown:
        print(f"python -m benchmarks: no benchmark {', '.join(unknown)} (known: {', '.join(known)})",
              file=sys.stderr)
        return 2
    for name in chosen:
        print(f"== benchmark {name}", flush=True)
        rc = load(name).main(args)
        if rc:
            return int(rc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
