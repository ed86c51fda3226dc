"""Shared fixtures: the repository's paths, the `c5` program (the JSON the bit-equality tests
compare with), robot files, and seeded random states."""

from __future__ import annotations

import json
import os
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_ROBOT = ROOT / "docs" / "default-robot.toml"


@pytest.fixture(scope="session")
def c5_program() -> Path:
    """The `c5` program of this checkout (`C5_PROGRAM` overrides), built if need be."""
    if "C5_PROGRAM" in os.environ:
        return Path(os.environ["C5_PROGRAM"])
    # Every command: the tests call `eval --derivatives` and `identify` too.
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "c5-cli", "--features", "full"],
                   cwd=ROOT, check=True)
    return ROOT / "target" / "release" / "c5"


@pytest.fixture(scope="session")
def run_c5(c5_program):
    """`c5 <command> [args]` on JSON lines: the parsed output lines."""

    def run(command: str, lines: list[dict], *args: str) -> list[dict]:
        text = "".join(json.dumps(line) + "\n" for line in lines)
        done = subprocess.run([str(c5_program), command, *args], input=text, text=True,
                              capture_output=True, check=True)
        return [json.loads(line) for line in done.stdout.splitlines()]

    return run


def toml_value(v) -> str:
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return repr(float(v))


def write_robot(doc: dict, path: Path) -> Path:
    """A robot file of the shape of docs/default-robot.toml."""
    out = [f"half_spacing = {toml_value(doc['half_spacing'])}",
           f"gravity = {toml_value(doc['gravity'])}", "", "[platform]"]
    out += [f"{k} = {toml_value(v)}" for k, v in doc["platform"].items()]
    for s in doc["segments"]:
        out += ["", "[[segments]]", "", "[segments.rod]"]
        out += [f"{k} = {toml_value(v)}" for k, v in s["rod"].items()]
        out += ["", "[segments.joint]"]
        out += [f"{k} = {toml_value(v)}" for k, v in s["joint"].items()]
    path.write_text("\n".join(out) + "\n")
    return path


@pytest.fixture(scope="session")
def unseen_robot(tmp_path_factory) -> Path:
    """A robot none of the Rust tests use: other spacing and masses, centres of mass off the
    reference points, inertias with products, gravity not along z."""
    doc = tomllib.loads(DEFAULT_ROBOT.read_text())
    doc["half_spacing"] = 0.23
    doc["gravity"] = [0.3, -0.2, -9.78]
    doc["platform"]["mass"] = 8.5
    doc["platform"]["com"] = [0.012, -0.008, 0.015]
    doc["platform"]["inertia"] = [[0.30, 0.01, -0.02], [0.01, 0.21, 0.005], [-0.02, 0.005, 0.17]]
    for i, s in enumerate(doc["segments"]):
        s["rod"]["mass"] = 1.5 + 0.1 * i
        s["joint"]["mass"] = 1.2 + 0.07 * i
        s["joint"]["com"] = [0.004 * (i - 2), 0.003, -0.002 * i]
        s["joint"]["inertia"] = [[0.006, 0.0004, 0.0], [0.0004, 0.005, -0.0003],
                                 [0.0, -0.0003, 0.004]]
    return write_robot(doc, tmp_path_factory.mktemp("robots") / "unseen.toml")


@pytest.fixture
def states():
    """Seeded random platform states in the workspace: `(pose, omega, velocity, omega_dot,
    acceleration)`, `n` rows."""

    def make(n: int, seed: int = 7):
        rng = np.random.default_rng(seed)
        pose = np.hstack([rng.uniform(-0.35, 0.35, (n, 3)), rng.uniform(-0.06, 0.06, (n, 3))])
        return (pose, *(rng.normal(scale=s, size=(n, 3)) for s in (0.8, 0.3, 4.0, 2.0)))

    return make
