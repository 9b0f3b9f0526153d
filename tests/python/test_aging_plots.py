"""scripts/plot.py's closed forms of the steady law with contact aging and its slide-hold-slide peaks (docs/model.md
§11.1, §11.4): the report draws and tests the models against these, so they are checked here against independent
numbers (a quadrature, the derivation's limits, a synthetic series whose peaks are known)."""
import math
import os
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import plot  # noqa: E402

P = (1.05, 8.0, 0.1)  # alpha, kappa, eta of the paper


def quadrature_exp_e1(x):
    """e^x E_1(x) = int_0^inf e^-t/(x + t) dt by the trapezoid rule on t = e^u, u in [-40, 5] (independent of
    plot.exp_e1's series and Gauss-Laguerre)."""
    u = np.linspace(-40.0, 5.0, 400001)
    t = np.exp(u)
    return float(np.trapz(np.exp(-t) * t / (x + t), u))


@pytest.mark.parametrize("x", [1e-3, 0.3, 0.999, 1.0, 3.0, 30.0])
def test_exp_e1_matches_a_quadrature(x):
    assert plot.exp_e1(x)[0] == pytest.approx(quadrature_exp_e1(x), rel=1e-6)


def test_exp_e1_known_value_and_continuity_at_the_switch():
    assert plot.exp_e1(1.0)[0] == pytest.approx(math.e * 0.21938393439552029, rel=1e-8)  # e E_1(1), A&S 5.1
    below, above = plot.exp_e1([1.0 - 1e-12, 1.0])
    assert below == pytest.approx(above, rel=1e-8)


def test_aged_law_without_aging_is_the_paper_law():
    v = np.geomspace(1e-3, 1e2, 17)
    assert np.allclose(plot.aged_sigma_ss(v, *P, 0.0, 1.0), plot.sigma_ss(v, *P), rtol=1e-14, atol=0)


def test_aged_law_log_rate_slope_is_minus_alpha_b_at_low_rates():
    alpha, b = P[0], 0.05
    v = np.array([1e-7, 1e-6])
    extra = plot.aged_sigma_ss(v, *P, b, 1.0) - plot.sigma_ss(v, *P)  # the aging's share of the law
    slope = (extra[1] - extra[0]) / math.log(v[1] / v[0])
    assert slope == pytest.approx(-alpha * b, rel=1e-3)


@pytest.mark.parametrize("b,tau", [(0.02, 0.1), (0.1, 1.0), (0.05, 10.0)])
def test_closure_offset_limits_of_the_derivation(b, tau):
    """closure - balance = alpha phi b f(x), f -> gamma as x -> 0 and 1/(2 x^2) as x -> inf (docs/model.md §11.4)."""
    alpha, kappa = P[0], P[1]
    for x, f in ((1e-9, np.euler_gamma), (300.0, 1.0 / (2.0 * 300.0 ** 2))):
        v = x / (kappa * tau)
        off = plot.aged_sigma_ss(v, *P, b, tau, closure=True) - plot.aged_sigma_ss(v, *P, b, tau)
        assert off[0] == pytest.approx(alpha * b * f / (1.0 + kappa * v), rel=2e-2)


def test_aged_minimum_lies_on_the_law_and_moves_little():
    vm, sc = plot.aged_minimum_of_friction(P, (0.05, 1.0))
    vm0, sc0 = plot.minimum_of_friction(*P)
    assert sc == pytest.approx(float(plot.aged_sigma_ss(vm, *P, 0.05, 1.0)[0]), rel=1e-12)
    for d in (0.999, 1.001):
        assert float(plot.aged_sigma_ss(vm * d, *P, 0.05, 1.0)[0]) >= sc
    assert sc > sc0 and abs(sc - sc0) < 1e-2 * sc0  # §11.5: 0.21667 -> ~0.2173 at b = 0.05


def test_hold_peaks_of_a_synthetic_slide_hold_slide():
    """Slides at v = 1, holds of 2 and 5 time units; sigma's peak in each later slide is known."""
    t = np.arange(0.0, 20.0, 0.5)
    v = np.where(((t >= 4) & (t < 6)) | ((t >= 10) & (t < 15)), 0.0, 1.0)
    sigma = np.full_like(t, 0.3)
    sigma[(t >= 6) & (t < 10)] = [0.9, 1.1, 0.8, 0.5, 0.4, 0.35, 0.3, 0.3]
    sigma[t >= 15] = np.linspace(1.4, 0.3, int((t >= 15).sum()))
    pk = plot.hold_peaks(t, v, sigma)
    assert pk.shape == (2, 3)
    assert pk[:, 0] == pytest.approx([2.0, 5.0])
    assert pk[:, 1] == pytest.approx([1.1, 1.4])
    assert pk[:, 2] == pytest.approx([0.3, 0.3])
    assert math.isnan(plot.peak_slope(pk, fit_from=10.0))
    assert plot.peak_slope(pk, fit_from=1.0) == pytest.approx(0.3 / math.log(2.5))
