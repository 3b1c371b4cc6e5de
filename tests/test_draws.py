"""``uavcov.draws.standard_normal`` is numpy's ``Generator.standard_normal``, bit for bit.

Values are compared with ``np.array_equal`` and the generators' states after with ``==``; the
ziggurat's tables are checked against numpy's own sampler, driven into each layer by crafted
PCG64 states (PCG64's output function and LCG step are invertible, so a state can be built
whose next outputs are any 64-bit words we like).
"""

from __future__ import annotations

import bisect
import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from uavcov import _core
from uavcov.cao import CAOSettings, cao, per_robot_cao
from uavcov.draws import standard_normal
from uavcov.errors import InvalidInputError, SurfaceTooLargeError

MULT = 0x2360ED051FC65DA44385DF649FCCF645
MASK128 = (1 << 128) - 1
MASK64 = (1 << 64) - 1
RABS_MASK = (1 << 52) - 1
R = 3.6541528853610088


def _load_tables() -> tuple[list[int], list[float], list[float]]:
    path = Path(__file__).resolve().parent.parent / "scripts" / "ziggurat_tables.py"
    spec = importlib.util.spec_from_file_location("ziggurat_tables", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["ziggurat_tables"] = module
    spec.loader.exec_module(module)
    return module.tables()


K, W, F = _load_tables()


# ---------------------------------------------------------------------------------------------
# Crafted PCG64 states
# ---------------------------------------------------------------------------------------------


def _rotl(x: int, r: int) -> int:
    return ((x << r) | (x >> (64 - r))) & MASK64 if r else x


def _state_giving(word: int, hi: int) -> int:
    """A state (after the step) whose XSL-RR output is ``word``, with ``hi`` as its high half."""
    return (hi << 64) | (_rotl(word, hi >> 58) ^ hi)


def _generator(state: int, inc: int) -> np.random.Generator:
    rng = np.random.Generator(np.random.PCG64(0))
    st = rng.bit_generator.state
    st["state"] = {"state": state, "inc": inc}
    rng.bit_generator.state = st
    return rng


def _crafted(first: int, second: int | None = None) -> tuple[int, int]:
    """``(state, inc)`` whose next output is ``first`` (and the one after, ``second``)."""
    s1 = _state_giving(first, 0x0123456789ABCDEF)
    if second is None:
        inc = 0xDA3E39CB94B95BDB
    else:
        # the increment is free: choose it so the step from s1 lands on a state giving `second`
        # (and odd, as numpy's always is; the high half's low bit makes it so)
        s2 = _state_giving(second, 0x0223456789ABCDEF)
        if not (s2 - s1 * MULT) & 1:
            s2 = _state_giving(second, 0x0223456789ABCDEE)
        inc = (s2 - s1 * MULT) & MASK128
    assert inc & 1
    return ((s1 - inc) * pow(MULT, -1, 1 << 128)) & MASK128, inc


def _steps(before: int, after: int, inc: int) -> int:
    """How many LCG steps lead from ``before`` to ``after`` (bit by bit, as PCG's distance)."""
    mult, distance, bit = MULT, 0, 1
    while before != after:
        if (before ^ after) & bit:
            before = (before * mult + inc) & MASK128
            distance |= bit
        inc = ((mult + 1) * inc) & MASK128
        mult = (mult * mult) & MASK128
        bit <<= 1
    return distance


def _word(idx: int, rabs: int, sign: int = 0) -> int:
    return idx | (sign << 8) | (rabs << 9)


def _draw_both(state: int, inc: int) -> tuple[float, int]:
    """One value from numpy and from uavcov at ``(state, inc)``: both must agree; returns the
    value and how many 64-bit draws it took."""
    ours, theirs = _generator(state, inc), _generator(state, inc)
    a = standard_normal(ours, 1)
    b = theirs.standard_normal(1)
    assert a.tobytes() == b.tobytes()
    assert ours.bit_generator.state == theirs.bit_generator.state
    return float(b[0]), _steps(state, theirs.bit_generator.state["state"]["state"], inc)


def test_crafted_states_give_the_words_asked_for():
    state, inc = _crafted(0xDEADBEEF12345678, 0x1111222233334444)
    assert _generator(state, inc).bit_generator.random_raw(2).tolist() == [0xDEADBEEF12345678, 0x1111222233334444]
    rng = _generator(state, inc)
    rng.bit_generator.random_raw(7)
    assert _steps(state, rng.bit_generator.state["state"]["state"], inc) == 7


# ---------------------------------------------------------------------------------------------
# The tables against numpy's sampler
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("sign", [0, 1])
def test_every_layer_width_is_numpys(sign):
    """A 52-bit part of 1 returns the layer's width exactly (layer 1, whose threshold is 0, via
    its wedge test, which such a point passes)."""
    for idx in range(256):
        value, _ = _draw_both(*_crafted(_word(idx, 1, sign)))
        assert value == (-W[idx] if sign else W[idx]), idx


def test_every_layer_threshold_is_numpys():
    """Below ``K[idx]`` a point is accepted with one draw; at ``K[idx]`` it is not."""
    for idx in range(256):
        if K[idx] > 0:
            assert _draw_both(*_crafted(_word(idx, K[idx] - 1)))[1] == 1, idx
        assert _draw_both(*_crafted(_word(idx, K[idx])))[1] > 1, idx


def _wedge_threshold(idx: int, x: float) -> int:
    """The least 53-bit uniform integer whose wedge test rejects ``x`` in layer ``idx``, as
    computed here with the tables (Python floats: IEEE doubles, no fused multiply-add)."""
    target = math.exp(-0.5 * x * x)
    return bisect.bisect_left(range(1 << 53), True, key=lambda m: (F[idx - 1] - F[idx]) * (m * 2.0**-53) + F[idx] >= target)


def test_the_wedge_boundaries_are_numpys():
    """In each layer and at three points, numpy accepts the last uniform before the boundary the
    tables predict and rejects the one on it: this pins ``F`` to well within an ulp (a boundary
    moves by tens of uniform steps per ulp of ``F``), and the test's arithmetic with it."""
    checked = 0
    for idx in range(1, 256):
        for frac in (0.25, 0.5, 0.75):
            rabs = K[idx] + int(frac * ((1 << 52) - K[idx]))
            x = rabs * W[idx]
            m = _wedge_threshold(idx, x)
            if not 0 < m < 1 << 53:
                continue
            accepted, steps = _draw_both(*_crafted(_word(idx, rabs), (m - 1) << 11))
            assert (accepted, steps) == (x, 2), (idx, frac)
            _, steps = _draw_both(*_crafted(_word(idx, rabs), m << 11))
            assert steps > 2, (idx, frac)
            checked += 1
    assert checked > 700


@pytest.mark.parametrize("sign, bit8", [(0, 0), (0, 1), (1, 0), (1, 1)])
def test_the_tail_is_numpys(sign, bit8):
    """Layer 0 beyond its threshold draws from the tail, whose sign numpy takes from bit 8 of
    the 52-bit part rather than from the sign bit."""
    rabs = (RABS_MASK & ~(1 << 8)) | (bit8 << 8)
    assert rabs >= K[0]
    for second in (1 << 11, 0x9E3779B97F4A7C15, MASK64):
        value, steps = _draw_both(*_crafted(_word(0, rabs, sign), second))
        assert abs(value) >= R and steps >= 3  # R plus a tiny excess can round to R
        assert (value < 0) == bool(bit8)


# ---------------------------------------------------------------------------------------------
# Streams
# ---------------------------------------------------------------------------------------------


def _paths_taken(state: int, inc: int, n: int) -> tuple[int, int]:
    """``(wedge tests, tail values)`` of numpy's sampler drawing ``n`` values from ``(state,
    inc)``, by replaying its decisions on the raw words (vectorised between rare events)."""
    raw = _generator(state, inc).bit_generator.random_raw(int(n * 1.05) + 1000).astype(np.uint64)
    idx = (raw & np.uint64(0xFF)).astype(np.intp)
    rabs = (raw >> np.uint64(9)) & np.uint64(RABS_MASK)
    slow = np.flatnonzero(rabs >= np.asarray(K, dtype=np.uint64)[idx]).tolist()
    uniform = (raw >> np.uint64(11)).astype(np.float64) * 2.0**-53
    wedges = tails = values = pos = 0
    while True:
        nxt = slow[bisect.bisect_left(slow, pos)]
        values += nxt - pos  # every point word before the next slow one is a value at once
        if values >= n:
            return wedges, tails
        i, pos = int(idx[nxt]), nxt + 1
        if i == 0:
            while True:
                xx = -math.log1p(-uniform[pos]) / R
                yy = -math.log1p(-uniform[pos + 1])
                pos += 2
                if yy + yy > xx * xx:
                    break
            tails += 1
            values += 1
            continue
        x = int(rabs[nxt]) * W[i]
        wedges += 1
        if (F[i - 1] - F[i]) * uniform[pos] + F[i] < math.exp(-0.5 * x * x):
            values += 1
        pos += 1


@pytest.mark.parametrize(
    "seed, shape",
    [
        (0, 0),
        (1, (0, 36)),
        (2, 1),
        (3, 7),
        (4, (200, 36)),
        (5, (3, 4, 5)),
        (6, ()),
        (2**63, (200, 12, 3)),
        (12345, 1_000_000),
        (99, (1000, 4000)),
        (7, 5_000_000),
    ],
)
def test_values_and_state_equal_numpys(seed, shape):
    ours, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
    for _ in range(2):  # twice: the second draw starts where the first left the state
        a, b = standard_normal(ours, shape), theirs.standard_normal(shape)
        assert a.dtype == np.float64 and a.shape == b.shape and a.flags.c_contiguous
        assert np.array_equal(a, b)
        assert ours.bit_generator.state == theirs.bit_generator.state


def test_a_million_values_cross_the_wedges_and_the_tail():
    """The stream of seed 12345's million values (checked above) takes both rare paths often."""
    st = np.random.default_rng(12345).bit_generator.state["state"]
    wedges, tails = _paths_taken(st["state"], st["inc"], 1_000_000)
    z = np.random.default_rng(12345).standard_normal(1_000_000)
    assert tails == np.count_nonzero(np.abs(z) > R) > 100
    assert wedges > 5_000


def test_many_seeds_and_sizes_equal_numpys():
    """A thousand seeds, some of them left mid-buffer by a 32-bit draw (with the streams above,
    over twenty million values in all)."""
    total = 0
    for seed in range(1000):
        ours, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
        if seed % 7 == 0:  # numpy buffers half a word for 32-bit draws: it must be kept as is
            ours.integers(0, 10, dtype=np.int32)
            theirs.integers(0, 10, dtype=np.int32)
        n = 2 * seed + 1 if seed % 10 else 3000 + 19 * seed
        assert np.array_equal(standard_normal(ours, n), theirs.standard_normal(n))
        assert ours.bit_generator.state == theirs.bit_generator.state
        total += n
    assert total > 200_000


@pytest.mark.parametrize("bit_generator", [np.random.MT19937(1), np.random.PCG64DXSM(1), np.random.Philox(1), np.random.SFC64(1)], ids=type)
def test_other_bit_generators_are_left_to_numpy(monkeypatch, bit_generator):
    def refuse(*args: object) -> None:
        raise AssertionError("the PCG64 kernel ran for another bit generator")

    ours = np.random.Generator(bit_generator)
    theirs = np.random.Generator(type(bit_generator)(1))
    monkeypatch.setattr(_core, "pcg64_standard_normal", refuse)
    assert np.array_equal(standard_normal(ours, (200, 36)), theirs.standard_normal((200, 36)))
    np.testing.assert_equal(ours.bit_generator.state, theirs.bit_generator.state)  # holds arrays


@pytest.mark.parametrize("optimizer", [cao, per_robot_cao])
def test_cao_draws_through_the_kernel_and_runs_as_with_numpy(monkeypatch, optimizer):
    calls = []
    kernel = _core.pcg64_standard_normal

    def spy(*args: int) -> tuple[np.ndarray, int]:
        calls.append(args[2])
        return kernel(*args)

    target = np.array([[3.0, -2.0, 5.0], [-4.0, 1.0, 6.0]])

    def measure(x: np.ndarray) -> float | tuple[float, np.ndarray]:
        parts = -np.sum((x - target) ** 2, axis=1)
        return float(parts.sum()) if optimizer is cao else (float(parts.sum()), parts)

    settings = CAOSettings(perturbation="gaussian")
    monkeypatch.setattr(_core, "pcg64_standard_normal", spy)
    ours = optimizer(measure, np.zeros((2, 3)), feasible=None, iterations=30, rng=5, settings=settings)
    assert len(calls) == 30
    monkeypatch.setattr(sys.modules["uavcov.cao"], "standard_normal", lambda rng, shape: rng.standard_normal(shape))
    theirs = optimizer(measure, np.zeros((2, 3)), feasible=None, iterations=30, rng=5, settings=settings)
    assert len(calls) == 30
    assert np.array_equal(ours.trajectory, theirs.trajectory)


# ---------------------------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------------------------


def test_bad_shapes_raise_and_leave_the_generator_alone():
    rng = np.random.default_rng(3)
    before = rng.bit_generator.state
    with pytest.raises(InvalidInputError, match="non-negative"):
        standard_normal(rng, (3, -1))
    with pytest.raises(TypeError):
        standard_normal(rng, (2.5,))  # type: ignore[arg-type]
    with pytest.raises(SurfaceTooLargeError):
        standard_normal(rng, (1 << 30, 1 << 30))
    assert rng.bit_generator.state == before


@pytest.mark.parametrize(
    "state, inc, n, error, match",
    [
        (1, 1, -1, InvalidInputError, "n must be >= 0"),
        (1, 1, 1 << 40, SurfaceTooLargeError, "more than"),
        (-1, 1, 1, InvalidInputError, "state must be an integer"),
        (1 << 128, 1, 1, InvalidInputError, "state must be an integer"),
        (1.0, 1, 1, InvalidInputError, "state must be an integer"),
        (1, -5, 1, InvalidInputError, "inc must be an integer"),
        (1, 1, 1 << 70, SurfaceTooLargeError, "more than"),
        (1, 1, -(1 << 70), InvalidInputError, "n must be >= 0"),
        (1, 1, 2.0, InvalidInputError, "n must be an integer"),
    ],
)
def test_the_kernel_refuses_bad_arguments(state, inc, n, error, match):
    with pytest.raises(error, match=match):
        _core.pcg64_standard_normal(state, inc, n)


def test_the_kernel_draws_nothing_for_zero():
    values, state = _core.pcg64_standard_normal(5, 7, 0)
    assert values.shape == (0,) and values.dtype == np.float64 and state == 5


def test_the_rust_tables_are_the_scripts_output():
    """``rust/ziggurat_tables.rs`` is what ``scripts/ziggurat_tables.py`` prints today."""
    generated = sys.modules["ziggurat_tables"].rust_source()
    committed = (Path(__file__).resolve().parent.parent / "rust" / "ziggurat_tables.rs").read_text()
    assert committed == generated
