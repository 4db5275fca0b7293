"""B₃ from the overlap indicators against exact results: thin rings (hard disks of diameter 2R) and parallel
squares, and against Monte Carlo on sesp's state-by-state overlap test for an open SeSP and a mixture."""

import math

import numpy as np
import pytest

from sesp import Polyline, SeSP
from sesp.virial import third_virial, third_virial_monte_carlo

SQUARE = Polyline([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1]])
DISKS = 4 / 3 - math.sqrt(3) / math.pi  # B₃/B₂² of hard disks: 0.7820044


def test_thin_rings_are_hard_disks_of_twice_their_radius():
    """Two thin rings of radius R meet exactly when hard disks of diameter 2R overlap."""
    b = third_virial(SeSP(n=2), rtol=None, nodes=301, nphi=4, segments=512)
    error = abs(float(b.reduced_third_virial) - DISKS)
    assert error < 1e-3 and error <= float(b.reduced_third_virial_error)
    assert float(b.second_virial_coefficient) == pytest.approx(2 * math.pi, rel=1e-5)  # B₂ = π(2R)²/2


def test_rtol_refines_the_lattice_until_the_bar_is_met_and_the_bar_holds():
    """Thin rings (orientation plays no part) to rtol 2e-3: the lattice is refined from 129 nodes until the bar
    is met, and the exact B₃ of hard disks lies within twice the bar (the bar is an estimate, not a bound: here
    the error is 1.6 times it); a lattice given too coarse says it was not met."""
    exact_b3 = DISKS * (2 * math.pi) ** 2
    b = third_virial(SeSP(n=2), rtol=2e-3, nphi=4, segments=256)
    assert b.attrs["converged"] == 1 and b.attrs["nodes"] > 129
    assert float(b.third_virial_coefficient_error) <= 2e-3 * float(b.third_virial_coefficient)
    assert abs(float(b.third_virial_coefficient) - exact_b3) <= 2 * float(b.third_virial_coefficient_error)
    with pytest.warns(UserWarning, match="rtol 1e-05 not met"):
        coarse = third_virial(SeSP(n=2), rtol=1e-5, nodes=41, nphi=4, segments=64)
    assert coarse.attrs["converged"] == 0 and coarse.attrs["nodes"] == 41


def test_parallel_squares():
    """Parallel hard squares of side a: B₂ = 2a², B₃ = 3a⁴, B₃/B₂² = 3/4."""
    b = third_virial(SQUARE, orientations="fixed", rtol=None, nodes=201)
    error = abs(float(b.reduced_third_virial) - 0.75)
    assert error < 1e-3 and error <= float(b.reduced_third_virial_error)
    assert abs(float(b.third_virial_coefficient) - 48.0) <= float(b.third_virial_coefficient_error)


def test_an_open_sesp_agrees_with_monte_carlo():
    """The ASP at Ψ = 90° (polygons of 64 segments for both): within 3 standard errors plus the lattice's bar."""
    asp = SeSP(n=2, opening=math.pi / 2)
    lattice = third_virial(asp, rtol=None, nodes=101, nphi=8, segments=64)
    sampled = third_virial_monte_carlo(asp, samples=40_000, seed=3, segments=64)
    difference = abs(float(lattice.third_virial_coefficient) - float(sampled.third_virial_coefficient))
    allowed = 3 * float(sampled.third_virial_coefficient_error) + float(lattice.third_virial_coefficient_error)
    assert difference <= allowed


def test_the_same_on_any_thread_count(threads):
    results = []
    for n in (1, 2):
        threads(n)
        results.append(third_virial(SeSP(n=2, opening=2.0), rtol=None, nodes=41, nphi=4, segments=32))
    assert results[0].third_virial_coefficient.item() == results[1].third_virial_coefficient.item()


def test_a_mixture_with_all_three_the_same_is_the_pure_value():
    asp = SeSP(n=2, opening=2.0)
    pure = third_virial(asp, rtol=None, nodes=41, nphi=4, segments=32)
    mixed = third_virial(asp, SeSP(n=2, opening=2.0), SeSP(n=2, opening=2.0), rtol=None, nodes=41, nphi=4, segments=32)
    np.testing.assert_allclose(float(mixed.third_virial_coefficient), float(pure.third_virial_coefficient), 1e-12)


MIXTURE = (SeSP(n=2, opening=math.pi / 2), SeSP(n=8, opening=math.pi), Polyline([[-1.0, 0.0], [1.0, 0.0]]))


@pytest.mark.slow
def test_a_mixture_of_three_different_particles_agrees_with_monte_carlo():
    """B₃,ᵢⱼₖ of an ASP (90°), a half-open n = 8 SeSP and a needle of length 2 (polygons of 64 segments): the
    lattice within 3 standard errors plus its bar of Mayer sampling on the state-by-state overlap test."""
    lattice = third_virial(*MIXTURE, rtol=None, nodes=101, nphi=32, segments=64)
    sampled = third_virial_monte_carlo(*MIXTURE, samples=400_000, seed=5, segments=64)
    difference = abs(float(lattice.third_virial_coefficient) - float(sampled.third_virial_coefficient))
    allowed = 3 * float(sampled.third_virial_coefficient_error) + float(lattice.third_virial_coefficient_error)
    assert difference <= allowed
    assert float(sampled.third_virial_coefficient_error) < 0.01 * float(sampled.third_virial_coefficient)


@pytest.mark.slow
def test_a_mixture_s_b3_does_not_depend_on_which_particle_is_first():
    """B₃,ᵢⱼₖ is symmetric in i, j, k: the three orders that put each particle at the origin agree within the
    sum of their error bars (the lattice decides different pairs in different frames)."""
    found = [third_virial(*(MIXTURE[i:] + MIXTURE[:i]), rtol=None, nodes=61, nphi=32, segments=32) for i in range(3)]
    values = [float(b.third_virial_coefficient) for b in found]
    bars = [float(b.third_virial_coefficient_error) for b in found]
    for i in range(3):
        for j in range(i):
            assert abs(values[i] - values[j]) <= bars[i] + bars[j]


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"nodes": 40}, "nodes must be odd"),
        ({"nphi": 5}, "nphi must be even"),
        ({"orientations": "x"}, "orientations"),
        ({"rtol": 0.0}, "rtol must be"),
        ({"rtol": math.nan}, "rtol"),
    ],
)
def test_bad_arguments_name_the_parameter(kwargs, word):
    with pytest.raises(ValueError, match=word):
        third_virial(SeSP(), **kwargs)


def test_a_lattice_that_would_not_fit_is_refused_before_any_work():
    """nodes = 4097 and 1024 orientations hold about 2 TiB: refused at once, naming the settings; the
    estimate covers what the default settings hold (E₁₂ and the spectra of E₁₃ over φ)."""
    from sesp.virial import held_bytes

    with pytest.raises(MemoryError, match="nodes=4097, nphi=1024"):
        third_virial(SeSP(n=2, opening=1.0), rtol=None, nodes=4097, nphi=1024)
    with pytest.raises(MemoryError, match="memory limit"):
        third_virial(SeSP(n=2, opening=1.0), rtol=None, nodes=41, nphi=4, memory_limit=held_bytes(41, 4, 4) - 1)
    per_slice = np.fft.rfft2(np.zeros((129, 129), dtype=bool), s=(258, 258)).nbytes
    assert held_bytes(129, 32, 4) >= 4 * 32 * (per_slice + 129 * 129)


def test_a_mixture_of_one_particle_under_two_names_has_its_b3():
    """Σᵢⱼₖ xᵢxⱼxₖ B₃,ᵢⱼₖ with every B₃,ᵢⱼₖ the same is that B₃, whatever the fractions: the weights of the
    multisets (1, 3, 3, 1 orders) add up to 1."""
    from sesp.virial import mixture_third_virial

    asp = SeSP(n=2, opening=2.0)
    settings = dict(rtol=None, b2_rtol=1e-3, nodes=21, nphi=4, segments=16, progress=False)
    pure = mixture_third_virial(asp, **settings)
    mixed = mixture_third_virial([asp, asp], [0.3, 0.7], **settings)
    assert float(mixed.third_virial_coefficient) == pytest.approx(float(pure.third_virial_coefficient), rel=1e-12)
    assert float(mixed.second_virial_coefficient) == pytest.approx(float(pure.second_virial_coefficient), rel=1e-12)
    alone = third_virial(asp, rtol=None, nodes=21, nphi=4, segments=16, progress=False)
    assert float(pure.third_virial_coefficient) == float(alone.third_virial_coefficient)
