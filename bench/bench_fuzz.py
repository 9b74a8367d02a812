"""The scenario/CLI fuzz test (tests/test_fuzz.py) with many more examples.

Runs the property tests exploring new examples (OMTP_HYPOTHESIS=explore) with OMTP_FUZZ_SCALE (default 20: 6000 documents through the
loader, 500 loaded and built and run for 50 ms, 400 through the CLI) and prints what
pytest reports; a failure prints Hypothesis's smallest failing document.

    python bench/bench_fuzz.py [--scale 20]
"""

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scale", type=float, default=20.0)
    args = parser.parse_args()
    root = Path(__file__).resolve().parent.parent
    env = dict(os.environ, OMTP_FUZZ_SCALE=str(args.scale), OMTP_HYPOTHESIS="explore")
    start = time.perf_counter()
    result = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                             str(root / "tests" / "test_fuzz.py"), "-k", "loader or builds or cli"],
                            env=env, capture_output=True, text=True)
    print(result.stdout.strip().splitlines()[-1] if result.stdout.strip() else result.stderr[-2000:])
    if result.returncode != 0:
        print(result.stdout[-6000:])
    print(f"scale {args.scale:g}: {300 * args.scale:.0f} loader, {25 * args.scale:.0f} build, "
          f"{20 * args.scale:.0f} CLI examples in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
