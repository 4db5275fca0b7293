"""Virial coefficients, orientational spectrum and Onsager instabilities against exact results."""

import math

import numpy as np
import pytest
import xarray as xr

from sesp import Grid, Polyline, SeSP, analyze
from sesp.measures import convex_excluded_area, shifted_excluded_area
from sesp.onsager import (
    contact_density,
    entangled_neighbours,
    first_transition,
    instabilities,
    mixture_second_virial,
    onsager_solution,
    onsager_variables,
    orientational_spectrum,
    parsons_lee_density,
    phase_behaviour,
    second_virial,
)

from cases import NEEDLE

L = 2.0  # NEEDLE's length


def _uniform(values_of_phi, nphi):
    phi = 2 * np.pi * np.arange(nphi) / nphi
    return xr.DataArray(values_of_phi(phi), coords={"phi": phi}, dims="phi", attrs={"units": "b^2"})


def _ring(radius, segments=256):
    theta = np.linspace(0, 2 * np.pi, segments + 1)
    theta[-1] = 0.0
    return Polyline(radius * np.column_stack([np.cos(theta), np.sin(theta)]))


def test_needle_spectrum_from_exact_samples_and_its_error_bars():
    for nphi in (64, 256):
        spectrum = orientational_spectrum(_uniform(lambda p: L**2 * np.abs(np.sin(p)), nphi), 6)
        exact_a2 = -4 * L**2 / (3 * math.pi)
        a2, err = float(spectrum.a.sel(k=2)), float(spectrum.a_error.sel(k=2))
        assert abs(a2 - exact_a2) <= err  # the bar covers the exact value
        if nphi == 256:
            assert abs(a2 / exact_a2 - 1) < 1e-3
        np.testing.assert_allclose(spectrum.b, 0, atol=1e-12)  # even in φ


def test_correlated_error_bars_bound_a_shared_error():
    """An error δ that every A_ex(φ) shares (a bias) moves a_0 by 2δ: the correlated propagation gives exactly
    that bound, the independent propagation far less; for k > 0 the bound is (2/nphi) Σ δ |cos kφ|."""
    nphi, delta = 64, 0.01
    area = _uniform(lambda p: 3.0 + np.cos(2 * p), nphi)
    error = xr.full_like(area, delta)
    bound = orientational_spectrum(area, 4, error=error, correlated=True)
    independent = orientational_spectrum(area, 4, error=error)
    biased = orientational_spectrum(area + delta, 4, error=0)
    shift = abs(float(biased.a.sel(k=0) - bound.a.sel(k=0)))
    assert shift == pytest.approx(2 * delta) and float(bound.a_error.sel(k=0)) == pytest.approx(2 * delta)
    assert float(independent.a_error.sel(k=0)) < 0.5 * shift
    expected = 2 / nphi * delta * np.abs(np.cos(2 * area.phi.values)).sum()
    assert float(bound.a_error.sel(k=2)) == pytest.approx(expected)


def test_needles_scanned_give_the_onsager_nematic_bifurcation():
    area = shifted_excluded_area(NEEDLE, Grid(512, nphi=256))
    assert float(second_virial(area)) * 2 == pytest.approx(2 * L**2 / math.pi, rel=1e-3)
    found = instabilities(area)
    assert int(found.leading_order) == 2
    rho = float(found.density.sel(order=2))
    assert rho * L**2 == pytest.approx(3 * math.pi / 2, rel=1e-3)
    assert float(found.reduced_density.sel(order=2)) == pytest.approx(3.0, rel=1e-3)
    exact_a2 = -4 * L**2 / (3 * math.pi)
    assert abs(float(found.a.sel(order=2)) - exact_a2) <= float(found.a_error.sel(order=2))  # the bar covers it
    assert np.isnan(found.density.sel(order=1))  # a₁ = 0: no polar instability


def test_rings_are_never_unstable():
    ring = _ring(0.8)
    area = shifted_excluded_area(ring, Grid(384, nphi=32))  # shifted: the fixed lattice's bias is shared by all φ
    assert float(second_virial(area)) == pytest.approx(2 * math.pi * 0.8**2, rel=1e-3)
    spectrum = orientational_spectrum(area, 8)
    assert np.all(np.abs(spectrum.a.sel(k=slice(1, None))) < 1e-3 * float(spectrum.a.sel(k=0)))
    higher = spectrum.sel(k=slice(1, 7))  # error bars are given for k < nphi / 4
    assert np.all(np.abs(higher.a) <= 3 * higher.a_error)  # the exact 0 lies within three error bars
    exact_a0 = 2 * 4 * math.pi * 0.8**2 * (1 - 1e-4)  # the 256-gon's A_ex sits ~1e-4 below the circle's
    assert abs(float(spectrum.a.sel(k=0)) - exact_a0) <= float(spectrum.a_error.sel(k=0)) + 2e-4 * exact_a0
    assert int(instabilities(area).leading_order) == 0


@pytest.mark.parametrize("n", [2, 4])
def test_closed_convex_b2_is_half_of_2a_plus_p2_over_2pi(n):
    particle = SeSP(n=n)
    area = shifted_excluded_area(particle, Grid(256, nphi=64), segments=256)
    exact = convex_excluded_area(particle.polyline(256)) / 2
    assert float(second_virial(area)) == pytest.approx(exact, rel=1e-3)
    spectrum = orientational_spectrum(area, 4)  # B2 = a0/4: its bar covers the exact value
    assert abs(float(spectrum.a.sel(k=0)) / 4 - exact) <= float(spectrum.a_error.sel(k=0)) / 4


@pytest.mark.parametrize("radius", [0.8, 1.25])
def test_needle_ring_mixture_cross_coefficient(radius):
    """L > 2R: A_ex = πR² + 2RL; L < 2R: minus the lens of positions where the needle fits inside."""
    ring = _ring(radius)
    cross = shifted_excluded_area(NEEDLE, Grid(768, nphi=16), other=ring)
    exact = math.pi * radius**2 + 2 * radius * L
    if L < 2 * radius:
        exact -= 2 * radius**2 * math.acos(L / (2 * radius)) - (L / 2) * math.sqrt(4 * radius**2 - L**2)
    assert float(cross.mean()) == pytest.approx(exact, rel=1e-3)  # B2 of the pair: < 1e-3 at 768² x 16
    np.testing.assert_allclose(cross.values, exact, rtol=2e-3)  # every φ
    needles = _uniform(lambda p: L**2 * np.abs(np.sin(p)), 16)
    rings = _uniform(lambda p: np.full_like(p, 4 * math.pi * radius**2), 16)
    table = [[needles, cross], [cross, rings]]
    matrix = mixture_second_virial(table, [0.5, 0.5]).second_virial_matrix
    assert float(matrix.sel(species_i=0, species_j=1)) == pytest.approx(float(cross.mean()) / 2)
    mixture = {x: float(mixture_second_virial(table, [x, 1 - x]).second_virial_coefficient) for x in (0, 0.5, 1)}
    assert mixture[1] == pytest.approx(float(second_virial(needles)))
    assert mixture[0] == pytest.approx(2 * math.pi * radius**2)
    half = 0.25 * (float(matrix[0, 0]) + 2 * float(matrix[0, 1]) + float(matrix[1, 1]))
    assert mixture[0.5] == pytest.approx(half)


def test_entanglement_and_contact_quantities_from_analyze():
    ds = analyze(SeSP(n=2, opening=math.pi / 2), Grid(48, nphi=16), segments=48, keep=["classes"], rtol=1e-3)
    assert float(ds.mean_entangled_area) > 0
    z = entangled_neighbours(ds.entangled_area, 0.5)
    assert float(z) == pytest.approx(0.5 * float(ds.entangled_area.mean()))
    assert float(contact_density(ds, 4.0)) * float(ds.mean_excluded_area) == pytest.approx(4.0)
    assert float(contact_density(ds.excluded_area, 4.0)) * float(ds.excluded_area.mean()) == pytest.approx(4.0)
    assert int(ds.leading_instability) in (0, 1, 2, 3, 4, 6)
    assert ds.spectrum_cos.dims == ("k",) and ds.instability_density.dims == ("order",)


@pytest.mark.parametrize(
    "call, word",
    [
        (lambda a: orientational_spectrum(a, 100), "order"),
        (lambda a: orientational_spectrum(a.isel(phi=[0, 1, 3]), 1), "uniform"),
        (lambda a: entangled_neighbours(a, -1), "density"),
        (lambda a: contact_density(a, 0), "contacts"),
        (lambda a: instabilities(a, [0]), "orders"),
    ],
)
def test_bad_arguments_name_the_parameter(call, word):
    with pytest.raises(ValueError, match=word):
        call(_uniform(lambda p: 1 + 0 * p, 16))


def test_thick_needle_spectrum_in_closed_form():
    """A_ex(φ) = L²|sin φ| + 4LD + πD²: the thickness shifts a₀ only."""
    thickness = 0.1
    constant = 4 * L * thickness + math.pi * thickness**2
    spectrum = orientational_spectrum(_uniform(lambda p: L**2 * np.abs(np.sin(p)) + constant, 256), 4)
    exact = {0: 4 * L**2 / math.pi + 2 * constant, 2: -4 * L**2 / (3 * math.pi), 4: -4 * L**2 / (15 * math.pi)}
    for k, value in exact.items():
        a, err = float(spectrum.a.sel(k=k)), float(spectrum.a_error.sel(k=k))
        assert abs(a - value) <= err and abs(a / value - 1) < 1e-3, k


def test_onsager_takes_what_excluded_area_returns_and_carries_its_error_bars():
    """B₂ of two needles of length 2 is ⟨4 |sin φ|⟩ / 2 = 4/π, with half of ⟨A_ex⟩'s bar; the instabilities
    run over ``order`` as in sweeps; the per-φ bars are carried as bounds."""
    from sesp import excluded_area
    from sesp.measures import scanline_excluded_area

    needle = Polyline([[-1.0, 0.0], [1.0, 0.0]])
    area = excluded_area(needle)
    b2 = second_virial(area)
    assert b2.name == "second_virial_coefficient" and float(b2) == pytest.approx(4 / math.pi, rel=1e-5)
    assert b2.attrs["error"] == pytest.approx(float(area.mean_excluded_area_error) / 2)
    on_64 = 2 * np.abs(np.sin(2 * np.pi * np.arange(64) / 64)).mean()  # the mean over those 64 orientations
    assert float(second_virial(scanline_excluded_area(needle, nphi=64))) == pytest.approx(on_64, rel=1e-6)
    found = instabilities(area)
    assert found.density.dims == ("order",) and int(found.leading_order) == 2
    bounds = orientational_spectrum(area.excluded_area, 4, error=area.excluded_area_error, correlated=True)
    xr.testing.assert_identical(orientational_spectrum(area, 4), bounds)
    variables = onsager_variables(area)
    assert float(variables["second_virial_coefficient_error"]) == pytest.approx(b2.attrs["error"])


@pytest.mark.parametrize(
    "call, word",
    [
        (lambda: second_virial(xr.Dataset({"other": 1.0})), "needs the variable excluded_area"),
        (lambda: second_virial(xr.DataArray([1.0, 2.0], dims="x")), "'phi' dimension"),
        (lambda: mixture_second_virial([[xr.DataArray(0.0)]], [1.5]), "fractions"),
        (lambda: onsager_solution(_uniform(lambda p: 1 + 0 * p, 16).expand_dims(n=[1, 2]), 1.0), "alone"),
        (lambda: onsager_solution(_uniform(lambda p: 1 + 0 * p, 16), -1.0), "density"),
        (lambda: phase_behaviour(_uniform(lambda p: 2 - np.cos(2 * p), 64), span=(2.0, 3.0)), "span"),
        (lambda: phase_behaviour(_uniform(lambda p: 2 - np.cos(2 * p), 64), points=1), "points"),
    ],
)
def test_bad_onsager_inputs_name_what_is_wrong(call, word):
    with pytest.raises(ValueError, match=word):
        call()


def test_too_few_orientations_give_b2_alone():
    found = onsager_variables(_uniform(lambda p: 2 + 0 * p, 2))
    assert set(found) == {"second_virial_coefficient"} and float(found["second_virial_coefficient"]) == 1.0


def _with_one_nan(values):
    values = values.copy()
    values[5] = np.nan
    return values


@pytest.mark.parametrize(
    "call",
    [second_virial, instabilities, first_transition, phase_behaviour, orientational_spectrum,
     lambda a: onsager_solution(a, 1.0), lambda a: contact_density(a, 4.0), lambda a: entangled_neighbours(a, 1.0),
     lambda a: orientational_spectrum(a.fillna(1.0), error=a)],
)  # fmt: skip
def test_a_non_finite_excluded_area_is_refused_where_it_is(call):
    """One NaN in A_ex(φ) is refused by every function that takes it, naming the φ where it is (not a NaN here
    and a finite density there)."""
    area = _uniform(lambda p: 2 - np.cos(2 * p), 64)
    area = area.copy(data=_with_one_nan(area.values))
    with pytest.raises(ValueError, match=r"must be finite .* the first at phi = 28.125°"):
        call(area)


def test_parsons_lee_refuses_non_finite_densities():
    with pytest.raises(ValueError, match="density must be finite"):
        parsons_lee_density([1.0, np.inf], 0.1)
