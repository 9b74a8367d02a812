"""The speed table: full runs against the bare plant (held still; same motion replayed), build, cycles.

    python bench/bench_speed.py [--repeats 2] [--bare-seconds 10]

The same as ``omtp-drake bench`` (the measurements live in bench/speed.py,
which documents the cases). For the CPU profile split, see bench/profile_split.py.
"""

from __future__ import annotations

import argparse
import logging

from speed import measure  # bench/speed.py (this directory is on the path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--bare-seconds", type=float, default=10.0)
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    logging.getLogger("omtp_drake").setLevel(logging.WARNING)
    print(
        measure(args.repeats, args.bare_seconds, progress=lambda text: print(f"measuring {text} ...")).table()
    )


if __name__ == "__main__":
    main()
