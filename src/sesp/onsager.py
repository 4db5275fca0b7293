"""From excluded area to phase behaviour: virial coefficients, orientational spectrum, Onsager instabilities.

Everything here works on A_ex(φ) over a uniform ``phi`` grid φ_j = 2πj / nphi:
what :func:`sesp.excluded_area` returns (a Dataset, whose error bars
``excluded_area_error(phi)`` and ``mean_excluded_area_error`` are then carried
through as bounds), the same variables of :func:`sesp.analyze` or a collected
sweep (whose other dimensions are carried along), or a bare DataArray
(:func:`sesp.measures.lattice_excluded_area` with ``by="phi"``,
:func:`sesp.measures.shifted_excluded_area`).

Orientational spectrum
----------------------
A_ex(φ) = a₀/2 + Σ_k (a_k cos kφ + b_k sin kφ), with
a_k = (1/π) ∫₀^{2π} A_ex(φ) cos kφ dφ (b_k with sin). For identical
particles A_ex(φ) = A_ex(−φ) and every b_k vanishes; mixtures keep them. On
the uniform grid the integral is the rectangle (periodic trapezoid) rule,
which is exact for the trigonometric polynomials of degree < nphi/2 and
converges as nphi⁻² for kinked A_ex(φ) such as |sin φ|, whose spectrum
decays only as k⁻²: a_k is usable for k well below nphi/2 (aliasing folds
a_{nphi−k} onto a_k), and no error bar is given for k >= nphi/4. The error
bar of each coefficient combines two parts:

* the φ-quadrature error, estimated as the difference from the same sum over
  every other φ (the coarser rule's error, which exceeds the finer one's);
* the per-φ errors of A_ex, propagated as independent errors: given by the
  caller, or by default estimated from the data as the robust scatter of the
  second differences of A_ex(φ) (1.4826 · median |Δ²A| / √6), which measures
  the lattice noise of grid results and is negligible for smooth exact
  samples. Where A_ex(−φ) is an exact copy of A_ex(φ) (mirror-symmetric
  pairs: only half the slices are computed) the propagated part is widened
  by √2. A bias shared by every φ (the fixed lattice's) is not seen by
  either part: use shifted lattices (:func:`sesp.measures.shifted_excluded_area`) for
  spectra. Error bars that may share their sign across φ (the scanlines',
  which :func:`sesp.analyze` stores) are propagated with ``correlated=True``
  as the bound (2/nphi) Σ |δA(φ) trig(kφ)|, which holds for any correlation.

Onsager theory in 2D
--------------------
B₂ = ⟨A_ex⟩/2 = a₀/4 (b²). With the second-virial free energy, the isotropic
state at number density ρ becomes unstable to k-fold orientational order
(k = 1 polar, 2 nematic, 4 tetratic, 6 hexatic) where 1 + ρ a_k / 2 = 0,
i.e. at ρ*_k = −2 / a_k for a_k < 0 (b⁻²); for thin needles of length L,
ρ*₂ L² = 3π/2 and the dimensionless ρ*₂ ⟨A_ex⟩ = 3. A coefficient counts as
negative only when it is below −3 times its error bar (``SIGNIFICANCE``),
so that lattice noise in a spectrum that should vanish (a closed circle's)
is not reported as an instability. The order with the smallest ρ*_k goes
unstable first. SeSPs have no head–tail
symmetry, so a₁ (polar) need not vanish.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .checks import check_count, check_finite, check_nonnegative, check_positive, check_range
from .units import link_errors, quantity

__all__ = [
    "orientational_spectrum",
    "second_virial",
    "mixture_second_virial",
    "instabilities",
    "entangled_neighbours",
    "contact_density",
    "ORDER_NAMES",
    "onsager_variables",
    "noise_estimate",
    "onsager_solution",
    "phase_behaviour",
    "first_transition",
    "particle_area",
    "parsons_lee_factor",
    "parsons_lee_density",
    "NeverUnstable",
]


class NeverUnstable(ValueError):
    """The isotropic state is stable at every density (no a_k is significantly negative): no transition."""


SIGNIFICANCE = 3.0  # a_k counts as negative below −SIGNIFICANCE error bars

ORDER_NAMES = {1: "polar", 2: "nematic", 3: "triatic", 4: "tetratic", 6: "hexatic"}


def _area_and_error(excluded_area, error, correlated):
    """A_ex(φ) as a DataArray, with the per-φ error to use: a Dataset's own bars ``excluded_area_error``
    (bounds, so correlated) unless an error is given."""
    if not isinstance(excluded_area, xr.Dataset):
        return excluded_area, error, correlated
    if "excluded_area" not in excluded_area:
        raise ValueError("a Dataset of A_ex needs the variable excluded_area(phi) (sesp.excluded_area returns one)")
    if isinstance(error, str) and error == "auto" and "excluded_area_error" in excluded_area:
        return excluded_area.excluded_area, excluded_area.excluded_area_error, True
    return excluded_area.excluded_area, error, correlated


def _has(excluded_area, name: str) -> bool:
    """Whether ``excluded_area`` is a Dataset holding the variable ``name``."""
    return isinstance(excluded_area, xr.Dataset) and name in excluded_area


def _mean_area(excluded_area) -> xr.DataArray:
    """⟨A_ex⟩ (b²): a Dataset's ``mean_excluded_area`` where it has one (the mean over the orientations
    :func:`sesp.excluded_area` refined to), else the mean of A_ex(φ) over its φ grid."""
    if _has(excluded_area, "mean_excluded_area"):
        return excluded_area.mean_excluded_area
    return _area(excluded_area).mean("phi")


def _area(excluded_area) -> xr.DataArray:
    return _area_and_error(excluded_area, 0.0, False)[0]


def _check_phi(excluded_area: xr.DataArray) -> np.ndarray:
    if not isinstance(excluded_area, xr.DataArray) or "phi" not in excluded_area.dims:
        raise ValueError("excluded_area must be a DataArray with a 'phi' dimension (A_ex(φ) in b²)")
    phi = excluded_area.phi.values
    nphi = len(phi)
    if nphi < 2 or not np.allclose(phi, 2 * np.pi * np.arange(nphi) / nphi, rtol=0, atol=1e-9):
        raise ValueError("phi must be the uniform grid 2πj/nphi, j = 0..nphi-1, with nphi >= 2")
    check_finite("excluded_area", excluded_area.transpose("phi", ...).values, " (b²)", _at_phi(phi))
    return phi


def _at_phi(phi):
    return ("phi = {:.6g}°", np.degrees(phi))


def _check_error(error, phi):
    """A per-φ error (b²) as given: "auto", None, or numbers >= 0 and finite (one, or one per φ)."""
    if error is None or (isinstance(error, str) and error == "auto"):
        return error
    values = error.transpose("phi", ...).values if isinstance(error, xr.DataArray) and "phi" in error.dims else error
    array = check_finite("error", values, " (b²)", _at_phi(phi) if np.ndim(values) else None)
    if np.any(array < 0):
        raise ValueError(f"error must be >= 0 (b²) everywhere, got a minimum of {array.min()!r}")
    return error


def noise_estimate(excluded_area: xr.DataArray) -> xr.DataArray:
    """Robust per-φ scatter of A_ex(φ) (b²): 1.4826 · median |Δ²A| / √6 over the periodic φ grid."""
    second = excluded_area.roll(phi=1) - 2 * excluded_area + excluded_area.roll(phi=-1)
    return (1.4826 / math.sqrt(6)) * abs(second).median("phi")


def _mirrored(excluded_area: xr.DataArray) -> bool:
    """Whether A_ex(φ_{nphi−k}) repeats A_ex(φ_k) exactly (mirror-symmetric pairs compute only half)."""
    values = excluded_area.transpose("phi", ...).values
    return bool(np.array_equal(values[1:], values[1:][::-1]))


def _coefficients(values: xr.DataArray, phi, order: int, trig) -> xr.DataArray:
    """(1/π) ∫ values · trig(kφ) dφ by the rectangle rule, k = 0..order, as a DataArray over k."""
    k = np.arange(order + 1)
    basis = xr.DataArray(trig(np.outer(k, phi)), dims=("k", "phi"), coords={"k": k})
    return (values * basis).sum("phi") * (2.0 / len(phi))


def orientational_spectrum(
    excluded_area: xr.DataArray, order: int = 8, *, error="auto", correlated: bool = False
) -> xr.Dataset:
    """Fourier coefficients a_k, b_k of A_ex(φ) with error bars (see the module notes).

    Parameters
    ----------
    excluded_area : xarray.DataArray or xarray.Dataset
        A_ex(φ) in b² over a uniform ``phi`` grid (other dimensions are kept),
        or a Dataset with ``excluded_area(phi)`` (see the module notes).
    order : int
        Largest k, 0 <= order < nphi / 2.
    error : "auto" or xarray.DataArray or float
        Standard error of each A_ex(φ) value (b²), independent between φ;
        "auto" (default): a Dataset's ``excluded_area_error`` as bounds, else
        estimated from the data (:func:`noise_estimate`); 0 counts the
        φ-quadrature error alone.
    correlated : bool
        Take ``error`` as bounds that may be correlated across φ: propagated as
        (2/nphi) Σ |error · trig(kφ)| instead of in quadrature.

    Returns
    -------
    xarray.Dataset
        Over ``k``: ``a`` (cosine coefficients, b²), ``b`` (sine, b²),
        ``a_error`` and ``b_error`` (b²).

    Examples
    --------
    >>> import numpy as np
    >>> import xarray as xr
    >>> from sesp.onsager import orientational_spectrum
    >>> phi = 2 * np.pi * np.arange(256) / 256
    >>> needles = xr.DataArray(4 * np.abs(np.sin(phi)), coords={"phi": phi}, dims="phi")
    >>> round(float(orientational_spectrum(needles, 2).a.sel(k=2)) / (-16 / (3 * np.pi)), 3)
    1.0
    """
    excluded_area, error, correlated = _area_and_error(excluded_area, error, correlated)
    phi = _check_phi(excluded_area)
    error = _check_error(error, phi)
    if isinstance(order, bool) or int(order) != order or not 0 <= order < len(phi) / 2:
        raise ValueError(f"order must be an integer in [0, nphi/2) = [0, {len(phi) / 2:g}), got {order!r}")
    order = int(order)
    out = {}
    for name, trig in (("a", np.cos), ("b", np.sin)):
        coeff = _coefficients(excluded_area, phi, order, trig)
        coarse = _coefficients(excluded_area.isel(phi=slice(0, None, 2)), phi[::2], order, trig)
        quadrature = abs(coeff - coarse)
        if len(phi) % 2 or order >= len(phi) / 4:  # no coarser rule resolves these k
            quadrature = quadrature.where(quadrature.k < len(phi) / 4, np.nan)
        propagated = 0.0
        per_phi = noise_estimate(excluded_area) if isinstance(error, str) and error == "auto" else error
        if per_phi is not None:
            k = np.arange(order + 1)
            basis = xr.DataArray(np.abs(trig(np.outer(k, phi))), dims=("k", "phi"), coords={"k": k})
            if correlated:
                propagated = (abs(xr.DataArray(per_phi)) * basis).sum("phi") * (2.0 / len(phi))
            else:
                propagated = np.sqrt((xr.DataArray(per_phi) ** 2 * basis**2).sum("phi")) * (2.0 / len(phi))
                if _mirrored(excluded_area):  # A(−φ) is a copy of A(φ): half as many independent errors
                    propagated = propagated * math.sqrt(2.0)
        out[name] = coeff.assign_attrs(**quantity(2, f"{'cosine' if name == 'a' else 'sine'} coefficient"))
        out[f"{name}_error"] = np.sqrt(quadrature**2 + propagated**2).assign_attrs(
            **quantity(2, f"error bar of {name}_k (quadrature in φ and propagated A_ex(φ) errors)")
        )
    ds = xr.Dataset(out)
    ds["k"].attrs.update(long_name="order k of the Fourier mode cos kφ", units="1")
    return link_errors(ds)


def second_virial(excluded_area) -> xr.DataArray:
    """B₂ = ⟨A_ex⟩ / 2 = a₀/4, in b² (the orientation average of A_ex(φ) over the uniform φ grid).

    From a Dataset with ``mean_excluded_area`` (:func:`sesp.excluded_area`, :func:`sesp.analyze`) ⟨A_ex⟩ is
    that variable, the mean over the orientations it was refined on; with ``mean_excluded_area_error`` the
    result carries its error bar, half of ⟨A_ex⟩'s, as the attribute ``error`` (b²; the largest over any
    other dimensions).
    """
    area = _area(excluded_area)
    _check_phi(area)
    b2 = (_mean_area(excluded_area) / 2).rename("second_virial_coefficient")
    b2 = b2.assign_attrs(**quantity(2, "second virial coefficient B2"))
    if _has(excluded_area, "mean_excluded_area_error"):
        b2.attrs["error"] = float(excluded_area.mean_excluded_area_error.max()) / 2
    return b2


def mixture_second_virial(areas, fractions) -> xr.Dataset:
    """B₂ of a mixture, Σᵢⱼ xᵢ xⱼ B₂,ᵢⱼ (b²), with B₂,ᵢⱼ = ⟨A_ex,ᵢⱼ⟩/2 (:func:`second_virial`).

    ``areas``: a square table (a list of rows) of A_ex between species i and j, each as
    :func:`second_virial` takes it (the table symmetric: A_ex,ᵢⱼ of the pair i, j with ``other`` j);
    ``fractions``: the mole fraction xᵢ of each species (≥ 0, summing to 1).

    Returns
    -------
    xarray.Dataset
        ``second_virial_coefficient`` (b²) of the mixture and ``second_virial_matrix`` over (``species_i``,
        ``species_j``); with error bars where every A_ex carries one (``_error``: Σᵢⱼ xᵢ xⱼ of the pairs').
    """
    x = np.asarray(fractions, dtype=float).ravel()
    if len(areas) != len(x) or any(len(row) != len(x) for row in areas):
        raise ValueError(f"areas must be a {len(x)} x {len(x)} table, one row and column per fraction")
    if np.any(~np.isfinite(x)) or np.any(x < 0) or abs(x.sum() - 1) > 1e-9:
        raise ValueError(f"fractions must be mole fractions >= 0 summing to 1, got {list(fractions)}")
    b2 = [[second_virial(a) for a in row] for row in areas]
    species = np.arange(len(x))
    matrix = xr.DataArray([[float(v) for v in row] for row in b2], dims=("species_i", "species_j"),
                          coords={"species_i": species, "species_j": species})  # fmt: skip
    weights = np.outer(x, x)
    out = xr.Dataset(
        {
            "second_virial_coefficient": ((), float((weights * matrix.values).sum()),
                                          quantity(2, "second virial coefficient B2 of the mixture")),
            "second_virial_matrix": matrix.assign_attrs(**quantity(2, "second virial coefficients B2_ij")),
            "fraction": ("species_i", x, {"units": "1", "long_name": "mole fraction of each species"}),
        }
    )  # fmt: skip
    if all("error" in v.attrs for row in b2 for v in row):
        errors = np.array([[v.attrs["error"] for v in row] for row in b2])
        out["second_virial_coefficient_error"] = (
            (),
            float((weights * errors).sum()),
            quantity(2, "error bar of B2"),
        )
        out["second_virial_matrix_error"] = (
            ("species_i", "species_j"),
            errors,
            quantity(2, "error bars of B2_ij"),
        )
    return link_errors(out)


def instabilities(excluded_area, orders=(1, 2, 3, 4, 6), *, error="auto", correlated: bool = False) -> xr.Dataset:
    """Where the isotropic state becomes unstable to k-fold order: ρ*_k = −2 / a_k for a_k < 0.

    ``excluded_area``, ``error`` and ``correlated`` as for :func:`orientational_spectrum`.

    Returns
    -------
    xarray.Dataset
        Over ``order`` = ``orders`` (the k of each instability, as sweeps store it): ``a`` and ``a_error`` (b²),
        ``density`` ρ*_k
        (b⁻², NaN where a_k >= 0: never unstable), ``density_error``,
        ``reduced_density`` ρ*_k ⟨A_ex⟩ (dimensionless) and its error; and
        ``leading_order``, the k with the smallest ρ*_k (0 if none).
    """
    orders = sorted({int(k) for k in orders})
    if not orders or orders[0] < 1:
        raise ValueError(f"orders must be integers >= 1, got {orders}")
    mean = _mean_area(excluded_area)
    excluded_area, error, correlated = _area_and_error(excluded_area, error, correlated)
    spectrum = orientational_spectrum(excluded_area, max(orders), error=error, correlated=correlated).sel(k=orders)
    spectrum = spectrum.rename(k="order")
    spectrum["order"].attrs.update(long_name="order k of the isotropic instability", units="1")
    a, a_error = spectrum.a, spectrum.a_error
    a0 = abs(mean) * 2
    unstable = (a < 0) & (-a > SIGNIFICANCE * a_error.fillna(0)) & (-a > 1e-9 * a0)
    density = (-2.0 / a).where(unstable)
    density_error = (2.0 * a_error / a**2).where(unstable)
    ds = xr.Dataset(
        {
            "a": a,
            "a_error": a_error,
            "density": density.assign_attrs(**quantity(-2, "isotropic instability density rho*_k")),
            "density_error": density_error.assign_attrs(**quantity(-2, "error bar of rho*_k")),
            "reduced_density": (density * mean).assign_attrs(units="1", long_name="rho*_k <A_ex>"),
            "reduced_density_error": (density_error * mean).assign_attrs(
                units="1", long_name="error bar of rho*_k <A_ex>"
            ),
        }
    )
    filled = density.fillna(np.inf)
    leading = filled.order[filled.argmin("order")].where(np.isfinite(filled.min("order")), 0)
    ds["leading_order"] = leading.drop_vars("order", errors="ignore").assign_attrs(
        long_name="k of the order that goes unstable first (0: none)", units="1"
    )
    return link_errors(ds)


def entangled_neighbours(entangled_area: xr.DataArray, density: float) -> xr.DataArray:
    """Mean number of entangled neighbours z = ρ ⟨A_ent⟩ at number density ``density`` (b⁻²).

    ``entangled_area`` is A_ent(φ) (b²), the area of positions entangled at
    each φ (:func:`sesp.analyze` with keep "classes" stores it).
    """
    _check_phi(entangled_area)
    rho = check_nonnegative("density", density, " (b^-2)")
    return (rho * entangled_area.mean("phi")).assign_attrs(units="1", long_name="mean entangled neighbours z")


def contact_density(excluded_area, contacts: float) -> xr.DataArray:
    """The density (b⁻²) at which the random-contact estimate ρ ⟨A_ex⟩ reaches ``contacts`` neighbours
    (⟨A_ex⟩ as for :func:`second_virial`)."""
    _check_phi(_area(excluded_area))
    z = check_positive("contacts", contacts)
    return (z / _mean_area(excluded_area)).assign_attrs(**quantity(-2, f"density of {z:g} mean contacts"))


def onsager_variables(excluded_area, order: int = 8, orders=(1, 2, 3, 4, 6), *, error="auto", correlated=False) -> dict:
    """B₂, the spectrum and the instabilities of A_ex(φ) as named variables (what sweeps store).

    ``spectrum_cos``/``spectrum_sin`` (and ``_error``) run over ``k`` = 0..order;
    the instabilities over ``order`` = ``orders`` (those below nphi/2). With
    fewer than 3 orientations only B₂ is returned. ``excluded_area``, ``error``
    and ``correlated`` as for :func:`orientational_spectrum`; from a Dataset with
    ``mean_excluded_area_error``, B₂'s error bar (half of it) is
    ``second_virial_coefficient_error``.
    """
    b2 = {"second_virial_coefficient": second_virial(excluded_area).drop_attrs()}
    b2["second_virial_coefficient"].attrs.update(**quantity(2, "second virial coefficient B2"))
    if _has(excluded_area, "mean_excluded_area_error"):
        b2["second_virial_coefficient_error"] = (excluded_area.mean_excluded_area_error / 2).assign_attrs(
            **quantity(2, "error bar of B2")
        )
    excluded_area, error, correlated = _area_and_error(excluded_area, error, correlated)
    order = min(order, (excluded_area.sizes["phi"] - 1) // 2)
    orders = [k for k in orders if k <= order]
    if not orders:  # too few orientations for a spectrum
        return b2
    spectrum = orientational_spectrum(excluded_area, order, error=error, correlated=correlated)
    unstable = instabilities(excluded_area, orders, error=error, correlated=correlated)
    return {
        **b2,
        "spectrum_cos": spectrum.a,
        "spectrum_cos_error": spectrum.a_error,
        "spectrum_sin": spectrum.b,
        "spectrum_sin_error": spectrum.b_error,
        "instability_density": unstable.density,
        "instability_density_error": unstable.density_error,
        "reduced_instability_density": unstable.reduced_density,
        "reduced_instability_density_error": unstable.reduced_density_error,
        "leading_instability": unstable.leading_order,
    }


# --- past the bifurcation: the second-virial free energy minimised over the orientational distribution ---

SOLVER_TOLERANCE = 1e-10  # largest change of ψ (rad⁻¹) at which the fixed-point iteration stops
SOLVER_STEPS = 20_000
ORDERED = 1e-6  # |⟨cos kφ⟩| above which a solution counts as ordered
MAX_DENSITY = 1e6  # b⁻²: the densest state solved for (for particles of size ~b, far past any ordering)


def _state(psi, values, density, dphi, particle_area: float = 0.0) -> dict:
    """Order parameters, free energy, pressure and chemical potential of the distribution ψ on the φ grid, at
    ``density`` (b⁻²) of the second-virial free energy, or of the Parsons–Lee one for ``particle_area`` > 0."""
    phi = np.arange(len(psi)) * dphi
    entropy = float(np.sum(psi * np.log(np.maximum(2 * np.pi * psi, 1e-300))) * dphi)
    energy = float(np.dot(psi, _convolved(values, psi, dphi)) * dphi)  # ∫∫ ψ ψ' A_ex(φ − φ')
    ks = np.arange(1, 7)
    order = np.array([np.sum(psi * np.cos(k * phi)) * dphi for k in ks])
    return {"psi": psi, "order": order, **_thermodynamics(density, entropy, energy, particle_area)}


def _excess_scale(density: float, particle_area: float) -> tuple[float, float]:
    """Φ(ρ) and dΦ/dρ, the density factor of the excess free energy βF_ex/N = Φ(ρ) · ½∫∫ψψ'A_ex: ρ and 1 in
    second-virial theory (``particle_area`` 0); ρ G(ρa) = [−ln(1 − η) + η/(1 − η)] / (2a), η = ρa, in
    Parsons–Lee theory (:func:`parsons_lee_factor`), whose slope is [1/(1 − η) + 1/(1 − η)²] / 2."""
    if particle_area == 0:
        return density, 1.0
    eta = density * particle_area
    if not 0 <= eta < 1:
        raise ValueError(f"packing fraction {eta:g} at density {density:g} b^-2: outside [0, 1)")
    scale = (-math.log1p(-eta) + eta / (1 - eta)) / (2 * particle_area)
    return scale, (1 / (1 - eta) + 1 / (1 - eta) ** 2) / 2


def _thermodynamics(density: float, entropy: float, energy: float, particle_area: float = 0.0) -> dict:
    """βF/N = ln ρ − 1 + σ + Φ(ρ) E/2 (σ = ∫ψ ln 2πψ, E = ∫∫ψψ'A_ex, Φ of :func:`_excess_scale`), its
    pressure βP = ρ² ∂(βF/N)/∂ρ = ρ + ρ² Φ'(ρ) E/2 (b⁻²) and chemical potential βμ = βF/N + βP/ρ."""
    scale, slope = _excess_scale(density, particle_area)
    return {
        "entropy": entropy,
        "energy": energy,
        "free_energy": math.log(density) - 1 + entropy + 0.5 * scale * energy,  # βF/N
        "pressure": density + 0.5 * density**2 * slope * energy,  # βP, b⁻²
        "chemical_potential": math.log(density) + entropy + 0.5 * (scale + density * slope) * energy,  # βμ
    }


def _convolved(values, psi, dphi) -> np.ndarray:
    """(A_ex ∗ ψ)(φ_i) = Σ_j A_ex(φ_i − φ_j) ψ_j Δφ: exact for the periodic rectangle rule, by FFT."""
    return np.fft.irfft(np.fft.rfft(values) * np.fft.rfft(psi), len(psi)) * dphi


def _symmetric(psi, fold: int) -> np.ndarray:
    """ψ averaged over turns by 2π/fold (where the grid has them): the k-fold part, which the iteration keeps."""
    if fold <= 1 or len(psi) % fold:
        return psi
    return np.mean([np.roll(psi, r * len(psi) // fold) for r in range(fold)], axis=0)


def _solved(values, density, seed, dphi, fold: int = 1, mixing=0.5):
    """The distribution ψ = exp(−ρ A_ex ∗ ψ) / Z reached from ``seed`` by damped fixed-point iteration, kept
    ``fold``-fold symmetric (rounding would otherwise grow into a less symmetric order where that is unstable).
    Near a bifurcation the iteration slows (a mode's factor nears 1); after SOLVER_STEPS it stops where it is."""
    psi = _symmetric(seed, fold) / (seed.sum() * dphi)
    for _ in range(SOLVER_STEPS):
        field = -density * _convolved(values, psi, dphi)
        new = _symmetric(np.exp(field - field.max()), fold)
        new /= new.sum() * dphi
        if float(np.abs(new - psi).max()) < SOLVER_TOLERANCE:
            return new
        psi = (1 - mixing) * psi + mixing * new
    return psi


def onsager_solution(
    excluded_area, density: float, order: int = 2, *, strength: float = 5.0, particle_area: float = 0.0
) -> xr.Dataset:
    """The orientational distribution that makes the second-virial free energy stationary at ``density``.

    βF/N = ln ρ − 1 + ∫ ψ ln(2πψ) dφ + (ρ/2) ∫∫ ψ(φ) ψ(φ') A_ex(φ − φ') dφ dφ', stationary where
    ψ = exp(−ρ A_ex ∗ ψ) / Z; solved on the φ grid of ``excluded_area`` (A_ex(φ) as for
    :func:`orientational_spectrum`; its convolution is exact for the grid's rectangle rule) by damped
    iteration from ψ ∝ exp(``strength`` cos(order·φ)), kept k-fold symmetric (k = ``order``; where the grid
    has turns by 2π/k): the k-fold solution where one exists, the isotropic one where none does. With
    ``particle_area`` a > 0 (b²) the free energy is Parsons–Lee's (:func:`phase_behaviour`).

    Returns
    -------
    xarray.Dataset
        ``psi`` (rad⁻¹, over ``phi``), ``order_parameter`` (⟨cos kφ⟩ over ``k`` = 1..6), and ``free_energy``
        (βF/N), ``pressure`` (βP, b⁻²) and ``chemical_potential`` (βμ).

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> from sesp.onsager import onsager_solution
    >>> phi = 2 * np.pi * np.arange(256) / 256
    >>> needles = xr.DataArray(np.abs(np.sin(phi)), coords={"phi": phi}, dims="phi")  # L = 1
    >>> solution = onsager_solution(needles, 3 * np.pi / 2 * 0.9)
    >>> bool(abs(solution.order_parameter.sel(k=2)) < 1e-6)  # isotropic below 3π/2
    True
    >>> round(float(onsager_solution(needles, 3 * np.pi / 2 * 1.2).order_parameter.sel(k=2)), 2)  # nematic
    0.62
    """
    area = _area(excluded_area)
    _check_phi(area)
    if area.ndim != 1:
        raise ValueError(f"excluded_area must be A_ex(φ) alone (dims ('phi',)), got dims {area.dims}")
    density = check_range("density", density, 1e-12, MAX_DENSITY, " b^-2")
    strength = check_nonnegative("strength", strength)
    order = check_count("order", order, 1, area.sizes["phi"] // 2, " (the fold of the seed)")
    values = area.values.astype(float)
    dphi = 2 * np.pi / len(values)
    phi = np.arange(len(values)) * dphi
    seed = np.exp(strength * np.cos(int(order) * phi))
    onsager = _excess_scale(density, particle_area)[0]  # the second-virial density with the same stationary ψ
    state = _state(_solved(values, onsager, seed, dphi, fold=int(order)), values, density, dphi, particle_area)
    return _state_dataset(state, area.phi)


def _state_dataset(state: dict, phi) -> xr.Dataset:
    """A state of :func:`_state` as labelled variables."""
    k = np.arange(1, len(state["order"]) + 1)
    return link_errors(
        xr.Dataset(
            {
                "psi": ("phi", state["psi"], {"units": "rad-1", "long_name": "orientational distribution psi"}),
                "order_parameter": ("k", state["order"], {"units": "1", "long_name": "<cos k phi>"}),
                "free_energy": ((), state["free_energy"], {"units": "1", "long_name": "beta F / N"}),
                "pressure": ((), state["pressure"], quantity(-2, "beta P")),
                "chemical_potential": ((), state["chemical_potential"], {"units": "1", "long_name": "beta mu"}),
            },
            coords={"phi": phi.values, "k": k},
        )
    )


def _isotropic_at(pressure: float, mean: float, particle_area: float) -> float:
    """b⁻²: the isotropic density of pressure βP (b⁻²), ⟨A_ex⟩ = ``mean``: ρ + ρ²⟨A_ex⟩/2 = βP solved for ρ
    (second virial), or its Parsons–Lee form ρ + ρ² Φ'(ρ) ⟨A_ex⟩/2 = βP by bisection (increasing in ρ)."""
    if particle_area == 0:
        return (-1 + math.sqrt(1 + 2 * mean * pressure)) / mean
    lo, hi = 0.0, 1.0 / particle_area
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if _thermodynamics(mid, 0.0, mean, particle_area)["pressure"] < pressure:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _coexistence(mean, branch, particle_area: float = 0.0):
    """Densities (ρ_I, ρ_O) of isotropic and ordered states of equal βP and βμ, from the ordered branch
    [(ρ, state), ...] (ascending ρ, states of the theory of ``particle_area``); None if it never crosses."""

    def gap(state):
        rho_i = _isotropic_at(state["pressure"], mean, particle_area)
        isotropic = _thermodynamics(rho_i, 0.0, mean, particle_area)  # ψ = 1/2π: σ = 0, E = ⟨A_ex⟩
        return isotropic["chemical_potential"] - state["chemical_potential"], rho_i

    gaps = [(rho, *gap(state)) for rho, state in branch]
    for (r0, g0, i0), (r1, g1, i1) in zip(gaps, gaps[1:], strict=False):
        if g0 * g1 <= 0 and g0 != g1:
            t = g0 / (g0 - g1)
            return i0 + t * (i1 - i0), r0 + t * (r1 - r0)
    return None


def _coarser(size: int, at_least: int) -> int:
    """The largest m dividing ``size`` with size / m >= ``at_least`` (1 if none)."""
    return max([m for m in range(1, size + 1) if size % m == 0 and size // m >= at_least], default=1)


def phase_behaviour(
    excluded_area,
    orders=(1, 2, 4),
    *,
    span=(0.5, 2.0),
    points: int = 61,
    nphi: int = 256,
    particle_area: float = 0.0,
) -> xr.Dataset:
    """Which order appears first as the density rises, and how: the Onsager solution past the bifurcations.

    For each k in ``orders`` with an isotropic instability ρ*_k (:func:`instabilities`; k must divide the
    number of orientations, so that the branch can be kept k-fold symmetric), the k-fold branch is
    followed over ρ in ``span`` × the first instability's density (``points`` densities, from the highest
    down, each solved from the one above); the order parameter ⟨cos kφ⟩, free energy, pressure and chemical
    potential are stored per density, and the stable phase is the solution of lowest free energy. A branch
    that exists below its ρ*_k (a subcritical bifurcation) gives a first-order transition: its coexisting
    densities (equal βP and βμ) are found on it; otherwise the transition is continuous at ρ*_k.

    With ``particle_area`` a > 0 (b², :func:`particle_area`) the free energy is Parsons–Lee's, the excess
    term scaled by the hard-disk fluid's G(ρa) (:func:`parsons_lee_density`): the stationary ψ at ρ is the
    second-virial one at ρG(ρa), so the branches are the same, relabelled in density; free energy, pressure
    and chemical potential are Parsons–Lee's, and so are the coexisting densities they give. Which phase is
    stable at a given ψ does not change (both theories differ from the isotropic state's by the same
    function of ψ times a positive factor). a = 0 is the second-virial theory.

    Returns
    -------
    xarray.Dataset
        Over ``density`` (b⁻²) and ``order``: ``order_parameter`` (⟨cos kφ⟩ of the k-fold branch, 0 where it
        is isotropic), ``free_energy`` (βF/N); over ``density``: ``stable_order`` (k of the stable phase, 0:
        isotropic); over ``order``: ``bifurcation_density`` ρ*_k, ``coexistence_low`` and
        ``coexistence_high`` (the isotropic and ordered coexisting densities; NaN for a continuous
        transition) and ``continuous`` (1: continuous, 0: first order, −1: ρ*_k outside the span).
    """
    area = _area(excluded_area)
    _check_phi(area)
    points = check_count("points", points, 3, 100_000, " densities")
    nphi = check_count("nphi", nphi, 8, 1 << 16, " orientations")
    span = tuple(check_positive("span", v, " (times the first instability's density)") for v in span)
    if len(span) != 2 or not span[0] < 1 < span[1]:
        raise ValueError(f"span must be two factors low < 1 < high of the first instability's density, got {span}")
    area = area.isel(phi=slice(0, None, _coarser(area.sizes["phi"], nphi)))
    # a k-fold branch is kept k-fold symmetric by averaging over turns by 2π/k: orders the grid has turns for
    found = instabilities(area, [k for k in orders if k < area.sizes["phi"] / 2 and area.sizes["phi"] % k == 0])
    unstable = found.density.dropna("order")
    if unstable.sizes["order"] == 0:
        raise NeverUnstable("the isotropic state never becomes unstable to these orders: no transition to follow")
    values = area.values.astype(float)
    first = float(unstable.min())
    onsager = np.linspace(span[0] * first, span[1] * first, int(points))  # where the branches are solved
    densities = np.asarray(parsons_lee_density(onsager, particle_area), dtype=float)  # the theory's own
    ks = [int(k) for k in unstable.order.values]
    columns, kinds = [], []
    for k in ks:
        order_parameter, free_energy, branch = _branch(values, k, onsager, densities, particle_area)
        columns.append((order_parameter, free_energy))
        kinds.append(_kind(order_parameter, branch, onsager, float(unstable.sel(order=k)), values, particle_area))
    order_parameter, free_energy = (np.column_stack(c) for c in zip(*columns))
    mean = float(values.mean())
    isotropic = np.array([_thermodynamics(rho, 0.0, mean, particle_area)["free_energy"] for rho in densities])
    stack = np.column_stack([isotropic, np.where(order_parameter != 0, free_energy, np.inf)])
    stable = np.array([0, *ks])[np.argmin(stack, axis=1)]
    low, high, continuous = (np.array(c) for c in zip(*kinds))
    bifurcation = np.asarray(parsons_lee_density(unstable.values, particle_area), dtype=float)
    return link_errors(xr.Dataset(
        {
            "order_parameter": (("density", "order"), order_parameter, {"units": "1", "long_name": "<cos k phi>"}),
            "free_energy": (("density", "order"), free_energy, {"units": "1", "long_name": "beta F / N"}),
            "stable_order": ("density", stable, {"units": "1", "long_name": "k of the stable phase (0: isotropic)"}),
            "bifurcation_density": ("order", bifurcation, quantity(-2, "rho*_k")),
            "coexistence_low": ("order", low, quantity(-2, "isotropic coexisting density")),
            "coexistence_high": ("order", high, quantity(-2, "ordered coexisting density")),
            "continuous": ("order", continuous.astype(int),
                           {"units": "1", "long_name": "1 continuous, 0 first order, -1 not reached"}),
        },
        coords={"density": ("density", densities, quantity(-2, "number density ρ")), "order": ks},
    ))  # fmt: skip


def _branch(values, k: int, onsager, densities, particle_area: float):
    """(order parameter, free energy, branch) of the k-fold branch at each density: solved at the second-virial
    densities ``onsager`` from the highest down, each from the one above; the order parameter 0 where the
    solution is isotropic; ``branch``: [(density, state), ...] of the ordered solutions."""
    dphi = 2 * np.pi / len(values)
    phi = np.arange(len(values)) * dphi
    order_parameter, free_energy = np.zeros(len(densities)), np.zeros(len(densities))
    psi = np.exp(5.0 * np.cos(k * phi))
    branch = []
    for i in range(len(densities) - 1, -1, -1):  # down in density, each from the one above
        psi = _solved(values, onsager[i], psi + 1e-3 * (1 + np.cos(k * phi)) / (2 * np.pi), dphi, fold=k)
        state = _state(psi, values, densities[i], dphi, particle_area)
        order_parameter[i] = state["order"][k - 1] if abs(state["order"][k - 1]) > ORDERED else 0.0
        free_energy[i] = state["free_energy"]
        if order_parameter[i]:
            branch.append((densities[i], state))
    return order_parameter, free_energy, branch


def _kind(order_parameter, branch, onsager, bifurcation: float, values, particle_area: float) -> tuple:
    """(low, high, continuous) of a branch: the coexisting densities of a first-order transition (NaN
    otherwise) and 1 continuous, 0 first order (the branch reaches below its bifurcation by more than the
    density step), −1 the bifurcation outside the densities solved."""
    points = len(onsager)
    below = [i for i in range(points) if order_parameter[i] and onsager[i] < bifurcation * (1 - 2 / points)]
    if not onsager[0] < bifurcation < onsager[-1]:
        return math.nan, math.nan, -1  # not reached in this span
    if not below:
        return math.nan, math.nan, 1
    pair = _coexistence(float(values.mean()), sorted(branch, key=lambda item: item[0]), particle_area)
    return (*pair, 0) if pair is not None else (math.nan, math.nan, 0)


def first_transition(excluded_area, orders=(1, 2, 4), *, particle_area: float = 0.0) -> xr.Dataset:
    """The first ordering transition as the density rises (see :func:`phase_behaviour`).

    Returns
    -------
    xarray.Dataset
        ``transition_order`` (k, 0 if none); ``transition_density`` (b⁻²: the bifurcation ρ*_k of a
        continuous transition, the isotropic coexisting density of a first-order one) and
        ``transition_density_error`` (b⁻², that of ρ*_k from :func:`instabilities` for a continuous
        transition; NaN for a first-order one, whose gap is not given a bar); ``ordered_density`` (the ordered
        coexisting density; equal to ``transition_density`` when continuous) and ``continuous`` (1, or 0 also
        for a branch that reaches below ρ*_k by less than the density step, whose coexistence gap is then not
        resolved: both densities are ρ*_k). ``particle_area`` > 0: in Parsons–Lee theory."""
    _check_phi(_area(excluded_area))
    try:
        found = phase_behaviour(excluded_area, orders, particle_area=particle_area)
    except NeverUnstable:  # no transition
        return _transition_dataset(0, math.nan, math.nan, math.nan, False)
    ordered = found.stable_order.where(found.stable_order > 0, drop=True)
    k = int(ordered[0]) if ordered.size else int(found.order[found.bifurcation_density.argmin()])
    row = found.sel(order=k)
    if int(row.continuous) == 0 and np.isfinite(float(row.coexistence_low)):
        return _transition_dataset(k, float(row.coexistence_low), math.nan, float(row.coexistence_high), False)
    density = float(row.bifurcation_density)
    bar = math.nan
    if int(row.continuous) == 1:  # ρ*_k on the full φ grid, and its bar (d ρ_PL / d ρ*_k ≤ 1: a bound)
        exact = instabilities(excluded_area, [k]).sel(order=k)
        density = float(parsons_lee_density(float(exact.density), particle_area))
        bar = float(exact.density_error)
    return _transition_dataset(k, density, bar, density, int(row.continuous) == 1)


def _transition_dataset(order: int, density: float, error: float, ordered: float, continuous: bool) -> xr.Dataset:
    said = "isotropic density at the first transition"
    return link_errors(xr.Dataset(
        {
            "transition_order": ((), order, {"units": "1", "long_name": "k of the first order (0: none)"}),
            "transition_density": ((), density, quantity(-2, said)),
            "transition_density_error": ((), error, quantity(-2, f"error bar of the {said} (NaN: none)")),
            "ordered_density": ((), ordered, quantity(-2, "ordered density at the first transition")),
            "continuous": ((), int(continuous), {"units": "1", "long_name": "1: continuous"}),
        }
    ))  # fmt: skip


# --- beyond the second virial: the Parsons–Lee rescaling ------------------------------------------------------


def particle_area(particle) -> float:
    """b²: the area a thick particle covers, L·D + πD²/4 for an open curve of length L and thickness D (L·D for
    a closed one); 0 for a thin particle.

    Exact where the curve's radius of curvature is at least D/2 everywhere and its parallel curves at ±D/2 do
    not meet (an arc of radius 1: the annular sector L·D and two half disks); SeSPs with sharp corners
    (large n) or openings narrower than D are covered less than that."""
    thickness = float(getattr(particle, "thickness", 0.0))
    closed = particle.is_closed if hasattr(particle, "is_closed") else float(particle.opening) == 0.0
    return float(particle.length) * thickness + (0.0 if closed else math.pi * thickness**2 / 4)


def parsons_lee_factor(packing_fraction):
    """G(η) = [−ln(1 − η) + η/(1 − η)] / (2η), G(0) = 1: the excess free energy of hard disks in scaled-particle
    theory over its second-virial value 2η (η: packing fraction, 0 ≤ η < 1). G = 1 + 3η/4 + O(η²)."""
    eta = np.asarray(packing_fraction, dtype=float)
    if np.any(~(eta >= 0) | ~(eta < 1)):
        raise ValueError(f"packing_fraction must lie in [0, 1), got {packing_fraction!r}")
    safe = np.where(eta == 0, 0.5, eta)  # both terms are positive: no cancellation down to the smallest η
    return np.where(eta == 0, 1.0, (-np.log1p(-safe) + safe / (1 - safe)) / (2 * safe))[()]


def parsons_lee_density(density, particle_area: float):
    """b⁻²: the density ρ at which the Parsons–Lee free energy has the orientational state that the
    second-virial (Onsager) free energy has at ``density`` (b⁻²): ρ G(ρ a) = ``density``, a the particle's
    area (b², :func:`particle_area`).

    The Parsons–Lee free energy is βF/N = ln ρ − 1 + ∫ψ ln(2πψ) + G(η) (ρ/2)∫∫ψψ'A_ex(φ − φ'), η = ρa: the
    second-virial excess term rescaled by the hard-disk fluid's (:func:`parsons_lee_factor`). Its stationary
    ψ is the Onsager one at ρG(η), so bifurcation densities ρ*_k (:func:`instabilities`) map exactly; the
    coexisting densities of a first-order transition do not (pressure and chemical potential change too):
    :func:`phase_behaviour` and :func:`first_transition` with ``particle_area`` give them.
    An approximation, not an exact result: see the guide. A thin particle (a = 0) keeps its density."""
    target = check_finite("density", density, " (b^-2)")
    if np.any(target < 0):
        raise ValueError(f"density must be >= 0 (b^-2), got a minimum of {target.min()!r}")
    area = check_nonnegative("particle_area", particle_area, " (b^2)")
    if area == 0:
        return target[()]
    goal = target * area  # η G(η) = ρ_O a: increasing in η from 0 to ∞ on [0, 1)
    lo, hi = np.zeros_like(goal), np.ones_like(goal)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        below = mid * parsons_lee_factor(np.minimum(mid, 1 - 1e-16)) < goal
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return (0.5 * (lo + hi) / area)[()]
