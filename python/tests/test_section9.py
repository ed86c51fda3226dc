"""The chapter's Section 9 from Python: the default robot's forces along the quintic move,
batched, against the peaks docs/section9.md reports from `cargo run --release -- simulate`,
and the statics the design brief states."""

from __future__ import annotations

import numpy as np
import pytest

import c5_kernels

# Peak |gamma| (N), actuators 1..6, from docs/section9.md.
PEAKS = {
    "consistent": [21.4, 8.0, 12.5, 12.4, 83.0, 83.1],
    "paper": [15.5, 13.3, 2.1, 2.1, 127.6, 120.8],
}


def section9_move(rate: float = 1000.0):
    """Constant orientation (10, 15, 20 degrees); the centre from the origin to
    (0.04, 0.03, 0.05) m, quintic rest to rest in 1 s."""
    t = np.linspace(0.0, 1.0, int(rate) + 1)
    s = 10 * t**3 - 15 * t**4 + 6 * t**5
    ds = 30 * t**2 - 60 * t**3 + 30 * t**4
    dds = 60 * t - 180 * t**2 + 120 * t**3
    end = np.array([0.04, 0.03, 0.05])
    pose = np.hstack([np.broadcast_to(np.radians([10.0, 15.0, 20.0]), (len(t), 3)),
                      np.outer(s, end)])
    zero = np.zeros((len(t), 3))
    return pose, zero, np.outer(ds, end), zero, np.outer(dds, end)


@pytest.mark.parametrize("model", ["consistent", "paper"])
def test_section9_peak_forces(model):
    gamma = c5_kernels.C5(model).inverse_dynamics(*section9_move())
    assert gamma.shape == (1001, 6)
    assert np.allclose(np.abs(gamma).max(axis=0), PEAKS[model], atol=0.05)


def test_statics_at_the_origin():
    """docs/models.md: at rest at zero orientation each vertical actuator carries
    (10/2 + 2 + 1.67) 9.81 = 85.05 N in the consistent model; the horizontal ones nothing."""
    gamma = c5_kernels.C5().inverse_dynamics(np.zeros(6))
    assert np.allclose(gamma, [0, 0, 0, 0, 85.0527, 85.0527], atol=1e-3)


def test_the_models_differ_as_the_docs_say():
    """README and docs/models.md: along Section 9 the paper model's forces differ from the
    mechanism's by up to 47.6 N (actuator 5, whose peak is 127.6 N); the table's column of
    largest differences, actuators 1..6."""
    move = section9_move()
    difference = np.abs(c5_kernels.C5("paper").inverse_dynamics(*move)
                        - c5_kernels.C5("consistent").inverse_dynamics(*move)).max(axis=0)
    assert np.allclose(difference, [8.8, 9.2, 12.9, 11.2, 47.6, 38.0], atol=0.05), difference
