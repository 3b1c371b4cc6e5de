"""``uavcov.optim._draws`` is numpy's ``Generator`` draws, bit for bit.

``standard_normal`` is ``Generator.standard_normal``; ``_core.pcg64_integers`` and
``_core.pcg64_random`` are ``Generator.integers`` (int64, ranges up to 2^32) and
``Generator.random``; ``redraw_monomials`` is CAO's monomial refresh with numpy's draws.

Values are compared with ``np.array_equal`` and the generators' states after with ``==`` (the
whole dict: the 32-bit buffer ``has_uint32``/``uinteger`` too); the ziggurat's tables and
Lemire's rejections are checked against numpy's own samplers, driven by crafted PCG64 states
(PCG64's output function and LCG step are invertible, so a state can be built whose next
outputs are any 64-bit words we like).
"""

from __future__ import annotations

import bisect
import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from uavcov import CAOSettings, _core
from uavcov.errors import InvalidInputError, SurfaceTooLargeError
from uavcov.optim import cao, per_robot_cao, standard_normal
from uavcov.optim._draws import redraw_monomials
from uavcov.optim._monomials import _draw_monomials, _first_terms, _n_distinct_monomials, _refresh_terms, _refresh_terms_numpy

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


def _generator(state: int, inc: int, has_uint32: int = 0, uinteger: int = 0) -> np.random.Generator:
    rng = np.random.Generator(np.random.PCG64(0))
    st = rng.bit_generator.state
    st["state"] = {"state": state, "inc": inc}
    st["has_uint32"], st["uinteger"] = has_uint32, uinteger
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
    monkeypatch.setattr(sys.modules["uavcov.optim._candidates"], "standard_normal", lambda rng, shape: rng.standard_normal(shape))
    theirs = optimizer(measure, np.zeros((2, 3)), feasible=None, iterations=30, rng=5, settings=settings)
    assert len(calls) == 30
    assert np.array_equal(ours.trajectory, theirs.trajectory)


# ---------------------------------------------------------------------------------------------
# Generator.integers and Generator.random
# ---------------------------------------------------------------------------------------------


def _integers(rng: np.random.Generator, low: int, high: int, n: int) -> np.ndarray:
    """``rng.integers(low, high, n)`` drawn by the kernel, the state read and written back."""
    st = rng.bit_generator.state
    words = st["state"]
    values, words["state"], st["has_uint32"], st["uinteger"] = _core.pcg64_integers(
        words["state"], words["inc"], st["has_uint32"], st["uinteger"], low, high, n
    )
    rng.bit_generator.state = st
    return values


def _random(rng: np.random.Generator, n: int) -> np.ndarray:
    st = rng.bit_generator.state
    values, st["state"]["state"] = _core.pcg64_random(st["state"]["state"], st["state"]["inc"], n)
    rng.bit_generator.state = st
    return values


RANGES = [1, 2, 3, 36, 37, 1000, 2**31 - 1, 2**31, 2**31 + 1, 2**32 - 5, 2**32 - 1, 2**32]


def test_integers_and_doubles_equal_numpys():
    """Every range of numpy's 32-bit path (one value: no draw; 2^32: raw 32-bit words; 2^31 + 1:
    Lemire rejects almost half the words), from states with and without a buffered half, and
    doubles between them, which must leave the buffer as it is."""
    checked = set()
    for seed in range(400):
        ours, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
        if seed % 2:  # enter with a buffered half
            ours.integers(0, 10, dtype=np.int32)
            theirs.integers(0, 10, dtype=np.int32)
        for step in range(3):
            span = RANGES[(seed + 5 * step) % len(RANGES)]
            low = (0, -7, 2**62, -(2**63))[(seed + step) % 4]
            n = (0, 1, 2, 3, 7, 36, 250)[(seed // 3 + step) % 7]
            a, b = _integers(ours, low, low + span, n), theirs.integers(low, low + span, n)
            assert a.dtype == np.int64 and np.array_equal(a, b)
            assert ours.bit_generator.state == theirs.bit_generator.state
            checked.add((span, ours.bit_generator.state["has_uint32"]))
            m = (0, 1, 5, 36)[(seed + step) % 4]
            assert np.array_equal(_random(ours, m), theirs.random(m))
            assert ours.bit_generator.state == theirs.bit_generator.state
    assert len(checked) == 2 * len(RANGES)  # every range, leaving the buffer full and empty


def _low_half_giving(leftover: int, n: int) -> int:
    """A 32-bit word ``x`` with ``x * n mod 2^32 == leftover`` (``leftover`` a multiple of the
    power of two in ``n``)."""
    twos = n & -n
    assert leftover % twos == 0
    modulus = (1 << 32) // twos
    return (leftover // twos) * pow(n // twos, -1, modulus) % modulus


@pytest.mark.parametrize("n", [3, 36, 37, 1000, 2**31 + 1, 2**32 - 5])
@pytest.mark.parametrize("buffered", [False, True])
def test_lemire_rejects_exactly_below_two_to_the_32_mod_n(n, buffered):
    """A word whose product with ``n`` leaves a low half below ``2^32 mod n`` is rejected and the
    next word decides; one whose low half is at the threshold is taken. Words come low half first,
    the high half kept for the next 32-bit draw (or the buffered half of the state first)."""
    threshold = (1 << 32) % n
    accepted = _low_half_giving(threshold, n)
    assert (accepted * n) % (1 << 32) == threshold
    for leftover in (0, threshold - 1):
        if leftover < 0 or leftover % (n & -n):
            continue
        rejected = _low_half_giving(leftover, n)
        if buffered:  # the rejected word waits in the buffer, the taken one is a low half
            state, inc = _crafted((0xABCDEF01 << 32) | accepted)
            args: tuple[int, int, int, int] = (state, inc, 1, rejected)
        else:
            state, inc = _crafted((accepted << 32) | rejected)
            args = (state, inc, 0, 0)
        ours, theirs = _generator(*args), _generator(*args)
        a, b = _integers(ours, 5, 5 + n, 1), theirs.integers(5, 5 + n, 1)
        assert a.tolist() == b.tolist() == [5 + (accepted * n >> 32)]
        assert ours.bit_generator.state == theirs.bit_generator.state
        assert theirs.bit_generator.state["has_uint32"] == int(buffered)
        assert _steps(state, theirs.bit_generator.state["state"]["state"], inc) == 1
    # at the threshold a word is taken: both halves of one 64-bit draw
    state, inc = _crafted((accepted << 32) | accepted)
    ours, theirs = _generator(state, inc), _generator(state, inc)
    assert _integers(ours, 0, n, 2).tolist() == theirs.integers(0, n, 2).tolist()
    assert ours.bit_generator.state == theirs.bit_generator.state
    assert theirs.bit_generator.state["has_uint32"] == 0  # two words from one 64-bit draw


# ---------------------------------------------------------------------------------------------
# CAO's monomial refresh
# ---------------------------------------------------------------------------------------------


def test_the_refresh_draws_numpys_monomials_and_leaves_numpys_state():
    """Thousands of refreshes, Rust against numpy: dims 1-80, up to 40 terms, keep fractions 0,
    0.3, 0.5 and 1, strengths with ties (and a few NaNs and signed zeros), generators with and
    without a buffered half; the few-variable cases go to numpy's ``choice`` on both sides."""
    rng = np.random.default_rng(2024)
    paths = {"kernel": 0, "choice": 0, "kept all": 0}
    for case in range(3000):
        dim = int(rng.integers(1, 81))
        n_terms = min(int(rng.integers(0, 41)), _n_distinct_monomials(dim))
        keep_fraction = (0.0, 0.3, 0.5, 1.0)[case % 4]
        terms = _draw_monomials(n_terms, dim, np.empty((0, 3), dtype=np.int64), rng)
        strength = rng.integers(0, 4, size=n_terms).astype(np.float64)
        if case % 10 == 0 and n_terms:
            strength[rng.integers(0, n_terms, size=2)] = (np.nan, -0.0)
        seed = int(rng.integers(1 << 63))
        ours, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
        if case % 3 == 0:
            ours.integers(0, 10, dtype=np.int32)
            theirs.integers(0, 10, dtype=np.int32)
        a = _refresh_terms(terms, strength, keep_fraction, dim, ours)
        b = _refresh_terms_numpy(terms, strength, keep_fraction, dim, theirs)
        assert a.dtype == np.int64 and np.array_equal(a, b), case
        assert ours.bit_generator.state == theirs.bit_generator.state, case
        n_keep = math.ceil(keep_fraction * n_terms)
        if n_keep >= n_terms:
            paths["kept all"] += 1
        elif 4 * n_terms > _n_distinct_monomials(dim):
            paths["choice"] += 1
        else:
            paths["kernel"] += 1
    assert min(paths.values()) > 100, paths


def test_the_first_monomials_are_numpys():
    for seed in range(300):
        dim, count = 1 + seed % 60, seed % 41
        if count > _n_distinct_monomials(dim):
            continue
        ours, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
        a = _first_terms(count, dim, ours)
        b = _draw_monomials(count, dim, np.empty((0, 3), dtype=np.int64), theirs)
        assert a.shape == (count, 3) and np.array_equal(a, b)
        assert ours.bit_generator.state == theirs.bit_generator.state


def test_the_kernel_defers_to_numpys_choice_without_drawing():
    rng = np.random.default_rng(8)
    before = rng.bit_generator.state
    terms = np.array([[0, 1, 2], [0, 0, 3]], dtype=np.int64)
    assert redraw_monomials(terms, np.ones(2), 1, 4, 3, rng) is None  # 4 (1 + 4) > 16 monomials
    assert redraw_monomials(terms, np.ones(2), 1, 3, 3, rng) is not None
    assert rng.bit_generator.state != before


@pytest.mark.parametrize("bit_generator", [np.random.MT19937(1), np.random.PCG64DXSM(1), np.random.SFC64(1)], ids=type)
def test_other_bit_generators_refresh_with_numpy(monkeypatch, bit_generator):
    def refuse(*args: object) -> None:
        raise AssertionError("the PCG64 kernel ran for another bit generator")

    monkeypatch.setattr(_core, "pcg64_monomials", refuse)
    terms = _draw_monomials(12, 36, np.empty((0, 3), dtype=np.int64), np.random.default_rng(0))
    strength = np.arange(12.0) % 5
    ours, theirs = np.random.Generator(bit_generator), np.random.Generator(type(bit_generator)(1))
    a = _refresh_terms(terms, strength, 0.5, 36, ours)
    assert np.array_equal(a, _refresh_terms_numpy(terms, strength, 0.5, 36, theirs))
    np.testing.assert_equal(ours.bit_generator.state, theirs.bit_generator.state)


def test_cao_refreshes_through_the_kernel_and_runs_as_with_numpy(monkeypatch):
    calls = []
    kernel = _core.pcg64_monomials

    def spy(*args: object) -> object:
        calls.append(args[3])
        return kernel(*args)  # type: ignore[arg-type]

    target = np.array([[3.0, -2.0, 5.0], [-4.0, 1.0, 6.0], [0.0, 0.0, 2.0], [1.0, 1.0, 1.0]])

    def measure(x: np.ndarray) -> float:
        return -float(np.sum((x - target) ** 2))

    monomials = sys.modules["uavcov.optim._monomials"]
    monkeypatch.setattr(_core, "pcg64_monomials", spy)
    ours = cao(measure, np.zeros((4, 3)), feasible=None, iterations=40, rng=11)
    assert len(calls) == 40 and calls[0] == 10  # the first 10 monomials, then one refresh an iteration
    monkeypatch.setattr(monomials, "redraw_monomials", lambda *args: None)
    theirs = cao(measure, np.zeros((4, 3)), feasible=None, iterations=40, rng=11)
    assert len(calls) == 40
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
    """``rust/cao/ziggurat_tables.rs`` is what ``scripts/ziggurat_tables.py`` prints today."""
    generated = sys.modules["ziggurat_tables"].rust_source()
    committed = (Path(__file__).resolve().parent.parent / "rust" / "cao" / "ziggurat_tables.rs").read_text()
    assert committed == generated


@pytest.mark.parametrize(
    "args, error, match",
    [
        ((1, 1, 2, 0, 0, 10, 1), InvalidInputError, "has_uint32 must be 0 or 1"),
        ((1, 1, -1, 0, 0, 10, 1), InvalidInputError, "has_uint32 must be 0 or 1"),
        ((1, 1, 1, 1 << 32, 0, 10, 1), InvalidInputError, "uinteger must be an integer"),
        ((1, 1, 0, 0, 0, 0, 1), InvalidInputError, "high - low must be in"),
        ((1, 1, 0, 0, 0, (1 << 32) + 1, 1), InvalidInputError, "high - low must be in"),
        ((1, 1, 0, 0, -(1 << 63), (1 << 63) - 1, 1), InvalidInputError, "high - low must be in"),
        ((1, 1, 0, 0, 0, 10, -1), InvalidInputError, "n must be >= 0"),
        ((1, 1, 0, 0, 0, 10, 1 << 40), SurfaceTooLargeError, "more than"),
        ((-1, 1, 0, 0, 0, 10, 1), InvalidInputError, "state must be an integer"),
    ],
)
def test_the_integer_kernel_refuses_bad_arguments(args, error, match):
    with pytest.raises(error, match=match):
        _core.pcg64_integers(*args)


def test_the_random_kernel_refuses_bad_arguments():
    with pytest.raises(InvalidInputError, match="n must be >= 0"):
        _core.pcg64_random(1, 1, -1)
    with pytest.raises(SurfaceTooLargeError, match="more than"):
        _core.pcg64_random(1, 1, 1 << 35)


_TERMS = np.array([[0, 1, 9], [2, 2, 2], [3, 4, 5]], dtype=np.int64)


@pytest.mark.parametrize(
    "terms, strength, keep, count, dim, error, match",
    [
        (np.zeros((3, 4), dtype=np.int64), np.ones(3), 1, 1, 9, InvalidInputError, "shape"),
        (_TERMS, np.ones(2), 1, 1, 9, InvalidInputError, "strength has 2 values for 3 terms"),
        (_TERMS, np.ones(3), 4, 1, 9, InvalidInputError, "cannot keep 4 of 3"),
        (_TERMS, np.ones(3), 1, 1, 8, InvalidInputError, "indices in"),
        (-_TERMS, np.ones(3), 1, 1, 9, InvalidInputError, "indices in"),
        (_TERMS, np.ones(3), 1, 1, (1 << 32) + 1, InvalidInputError, "dim must be at most"),
        (_TERMS, np.ones(3), 1, 1 << 29, 1 << 20, SurfaceTooLargeError, "more than"),
        (_TERMS, np.ones(3), 1, 1 << 70, 1 << 20, SurfaceTooLargeError, "more than"),
        (_TERMS[:0], np.ones(0), 0, 17, 3, InvalidInputError, "cannot draw 17 new monomials"),
        (_TERMS, np.ones(3), -1, 1, 9, InvalidInputError, "keep must be >= 0"),
        (_TERMS, np.ones(3), 1, 1.0, 9, InvalidInputError, "count must be an integer"),
    ],
)
def test_the_monomial_kernel_refuses_bad_arguments(terms, strength, keep, count, dim, error, match):
    rng = np.random.default_rng(4)
    before = rng.bit_generator.state
    with pytest.raises(error, match=match):
        redraw_monomials(terms, strength, keep, count, dim, rng)
    assert rng.bit_generator.state == before
