"""The README's two commands and the CI script stay in step."""

import io
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = text.split("```bash", 1)[1].split("```", 1)[0]
    return [ln.strip() for ln in block.splitlines() if ln.strip() and not ln.startswith("#")]


def test_readme_opens_with_demo_and_test_commands():
    first, second = _readme_commands()[:2]
    assert first.endswith("presliding demo")
    assert "pip install" in first and "pip install" in second
    assert ".[test]" in second


def test_ci_runs_both_readme_commands_as_written():
    """.ci/run reads the README's block with the same rule and runs both lines unchanged."""
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    extractor = ci.split("<<'PY'\n", 1)[1].split("\nPY\n", 1)[0]
    printed: list[str] = []
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    namespace = {"open": lambda *a, **k: io.StringIO(readme), "print": printed.append}
    exec(compile(extractor, ".ci/run", "exec"), namespace)
    assert printed[:2] == _readme_commands()[:2]
    run_lines = [ln.strip() for ln in ci.splitlines() if not ln.strip().startswith("#")]
    # the main job with an empty numba cache and no extras, then the tests
    assert any('eval "$main_cmd"' in ln and "NUMBA_CACHE_DIR" in ln for ln in run_lines)
    assert any('eval "$test_cmd"' in ln for ln in run_lines)
    assert ci.index('eval "$main_cmd"') < ci.index('eval "$test_cmd"')
    assert "presliding-demo/report.html" in ci
    assert '"$rc" -eq 5' in ci  # pytest collecting nothing is a failure


def test_readme_python_examples_run():
    import matplotlib.pyplot as plt

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = [b.split("```", 1)[0] for b in text.split("```python")[1:]]
    assert blocks, "README has no python example"
    spaces = []
    for block in blocks:
        namespace: dict[str, object] = {}
        exec(compile(block, "README.md", "exec"), namespace)
        spaces.append(namespace)
    # the first look ends with a free stop and its plot
    namespace = spaces[0]
    tp = namespace["tp"]
    assert tp.success and tp.n_reversals >= 1
    assert namespace["ax"].lines
    # the control example: the exact loop settles on the predicted hunting cycle
    if len(spaces) > 1 and "cycles" in spaces[-1]:
        loop, cycles = spaces[-1]["res"].limit_cycle(), spaces[-1]["cycles"]
        assert loop.steady and abs(loop.amplitude / cycles.amplitude[0] - 1) < 0.01
    plt.close("all")


def test_the_model_file_example_comes_to_rest(tmp_path, capsys):
    """README's model file simulates a free stop (no offset pushing the mass), exit 0."""
    import numpy as np

    from presliding.cli import main

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    example = text.split("```toml", 1)[1].split("```", 1)[0]
    assert "[friction]" in example and "[motion]" in example
    path = tmp_path / "model.toml"
    path.write_text(example, encoding="utf-8")
    out = tmp_path / "run"
    assert main(["simulate", str(path), "-o", str(out)]) == 0
    assert "stops at" in capsys.readouterr().out
    data = np.loadtxt(out / "simulation.csv", delimiter=",", skiprows=1)
    assert data[-1, 2] == 0.0 and np.all(data[:, 6] == 0.0)  # at rest; no force applied


def test_the_readmes_interconnect_example_connects_every_signal_without_a_warning():
    """``outputs=["position", "u"]`` left the mass's velocity unconnected: python-control
    warned (UserWarning: Unused output(s) in InterconnectedSystem)."""
    import re
    import warnings

    import control
    import presliding as ps

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    found = re.search(r"`(control\.interconnect\(.*?\))`", text, re.S)
    assert found, "the README's interconnect example"
    code = " ".join(found.group(1).split())
    model = ps.PIFriction(coulomb=0.5, stiffness=[500.0, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])
    pid = ps.PID(400.0, 4e4, 0.0, dt=1e-4, limit=5.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loop = eval(code, {"control": control, "ps": ps, "model": model, "pid": pid})
    assert loop.output_labels == ["position", "velocity", "u"]
