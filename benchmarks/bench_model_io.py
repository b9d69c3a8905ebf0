"""Model files with long element arrays: save and load times, and what they are made of.

A `PIFriction` of N random elements (stiffness and break-away arrays of N numbers each,
the shortest repr of each float) is saved with `save_model` and read back with
`load_model`; the script checks that every number comes back bit for bit and prints

* the seconds to save, to read the tables (`read_tables`: the TOML text and its arrays),
  to construct the model from the arrays in memory (`PIFriction`, no file involved) and
  to load the model (`load_model`: both), each the best of `--repeats`, wall and CPU
  (the first read also loads the compiled scanner from its cache, or compiles it once);
  ``--order sorted`` gives the elements in increasing threshold (a discretised density or
  a compiled network), ``random`` (default) in random order, which the construction
  sorts;
* the file's size and the peak memory numpy and Python allocated while loading;
* against tomllib on the first `--tomllib` numbers (it parses one number at a time, so the
  whole file would take minutes): seconds per million numbers of both and their ratio,
  measured in the same run.

Target: a model with 1e7-element arrays loads in under 5 s::

    python benchmarks/bench_model_io.py [--elements 10000000] [--repeats 2] [--tomllib 200000]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from presliding import PIFriction
from presliding.model_io import load_model, read_tables, save_model

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


#: CPU seconds of the best repeat of each `best` call (a shared machine inflates wall time).
CPU: list[float] = []


def best(call, repeats: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeats):
        start, cpu = time.perf_counter(), time.process_time()
        result = call()
        times.append((time.perf_counter() - start, time.process_time() - cpu))
    wall, used = min(times)
    CPU.append(used)
    return wall, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=float, default=1e7)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--tomllib", type=int, default=200_000)
    parser.add_argument("--order", choices=("random", "sorted"), default="random")
    args = parser.parse_args()
    n = int(args.elements)
    rng = np.random.default_rng(0)
    k, c = rng.uniform(1.0, 1e4, n), rng.uniform(1e-3, 1.0, n)
    if args.order == "sorted":
        c = k * np.sort(c / k)  # thresholds r = c/k increasing
    k[:4], c[:4] = [5e-324, 1e300, 2.5e-308, 1 / 3], [1e-300, 7.0, 0.1, 2.0**-1074 * 3]
    model = PIFriction(0.3, k, c)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "model.toml"

        def save() -> None:
            save_model(path, model, overwrite=True)

        t_save, _ = best(save, args.repeats)
        size = path.stat().st_size
        start = time.perf_counter()
        read_tables(path)  # the compiled scanner: from its cache (or compiled) once
        t_first = time.perf_counter() - start
        t_tables, _ = best(lambda: read_tables(path), args.repeats)
        t_model, _ = best(lambda: PIFriction(0.3, k, c), args.repeats)
        t_load, spec = best(lambda: load_model(path), args.repeats)
        assert np.array_equal(spec.model.stiffness.view(np.int64), k.view(np.int64))
        assert np.array_equal(spec.model.breakaway.view(np.int64), c.view(np.int64))
        tracemalloc.start()
        load_model(path)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        print(f"{n:.3g} elements ({args.order} order), file {size / 1e6:.0f} MB, "
              "every number read back bit for bit")  # fmt: skip
        cpu_save, cpu_tables, cpu_model, cpu_load = CPU[:4]
        print(f"save_model   {t_save:7.2f} s wall, {cpu_save:6.2f} s CPU")
        first = f"(first call {t_first:.2f} s)"
        print(f"read_tables  {t_tables:7.2f} s wall, {cpu_tables:6.2f} s CPU {first}")
        print(f"PIFriction   {t_model:7.2f} s wall, {cpu_model:6.2f} s CPU (from the arrays)")
        print(f"load_model   {t_load:7.2f} s wall, {cpu_load:6.2f} s CPU, target < 5 s"
              f"{'' if t_load < 5 else '  MISSED'}")  # fmt: skip
        print(
            f"peak memory while loading {peak / 1e6:.0f} MB (the arrays: {2 * 8 * n / 1e6:.0f} MB)"
        )
        m = min(args.tomllib, n)
        if m:
            text = path.read_text(encoding="utf-8")
            head = text[: text.index("[")] + "[friction]\nstiffness = ["
            body = ", ".join(map(repr, k[:m].tolist()))
            small = (head + body + "]\n").encode()
            t_toml, parsed = best(lambda: tomllib.loads(small.decode()), 1)
            small_path = Path(folder) / "small.toml"
            small_path.write_bytes(small)
            t_fast, fast = best(lambda: read_tables(small_path), args.repeats)
            assert np.array_equal(
                np.asarray(parsed["friction"]["stiffness"]), fast["friction"]["stiffness"]
            )
            per = 1e6 / m
            print(f"{m} numbers: tomllib {t_toml * per:.2f} s per million, read_tables "
                  f"{t_fast * per:.3f} s per million, ratio {t_toml / t_fast:.0f}x")  # fmt: skip


if __name__ == "__main__":
    main()
