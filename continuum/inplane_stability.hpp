#pragma once
// The linear stability of homogeneous sliding on the in-plane strip under the normal-load coupling
// (docs/model.md §12.6): the growth rates s of a perturbation ∝ e^{ikx + st} of steady sliding at v_0 on the
// strengthening branch, the strip's Lamé equations discretised in y only (linear elements, exact integration, lumped
// mass; x exact through e^{ikx}), the law of docs/model.md §12.1 linearised about its steady state, the load
// p = −σ_yy(x, 0) the reaction that holds u_y = 0 (as core::InPlane reads it). The eigenvalues of the resulting
// first-order system (Eigen's ComplexEigenSolver) are the growth rates of every mode of that k.
#include <complex>
#include <vector>

namespace slipfront::continuum {

struct InPlaneStabilityParams {
  double mu_p = 1.0, lambda_p = 1.0, rho_p = 1.0, height = 1.0;  ///< μ', λ', ρ', H (docs/model.md §10.2)
  double alpha = 1.05, kappa = 8.0, eta = 0.1;                   ///< the law (docs/model.md §1.1)
  double v0 = 2.0;            ///< the sliding rate (strengthening branch: v0 > v_m)
  double p0 = 1.0;            ///< the reference load (bulk.normal_load)
  double exponent = 1.0;      ///< m of a = (p/p_0)^m
  bool coupled = true;        ///< false: the law sees no load (interface.load_coupling = "none")
  bool instantaneous = false; ///< the channel (interface.load_channel)
  /// The regularisation of the instantaneous channel (docs/model.md §12.7, Prakash–Clifton): the law sees p_eff with
  /// ṗ_eff = −((|v| + v*)/L)(p_eff − p); relaxation_length L = 0: off (p_eff = p, today's channel).
  double relaxation_length = 0.0, relaxation_speed = 0.0;  ///< L, v* (interface.load_relaxation_length, _speed)
  int elements = 64;          ///< linear elements over the height
};

/// One mode e^{ikx + st} (docs/model.md §12.6): the rows' amplitudes of u_x, u_y (u_y(0) = 0) and their rates, and the
/// law's two perturbations (re-attachment: δA, δσ̄; instantaneous: δφ, δψ with σ̄ = aψ, A = aφ), and the regularised
/// load's δp_eff (0 without the regularisation), scaled to δv = 1.
struct InPlaneMode {
  std::complex<double> s;
  std::vector<std::complex<double>> ux, uy, vx, vy;  ///< rows j = 0..elements
  std::complex<double> law_a, law_b, p_eff;
};

/// The growth rates (every eigenvalue) at wavenumber k > 0.
std::vector<std::complex<double>> inplane_growth_rates(const InPlaneStabilityParams& p, double k);
/// The eigenvalue of largest real part among those with |Im s| ≤ max_frequency (the resolved modes).
std::complex<double> leading_growth_rate(const InPlaneStabilityParams& p, double k, double max_frequency);
/// The leading mode (the largest Re s among |Im s| ≤ max_frequency; on a tie the one with Im s ≥ 0) with its shape.
InPlaneMode leading_mode(const InPlaneStabilityParams& p, double k, double max_frequency);
/// The static kernels of the discretisation: σ_xy(x, 0) = K_t U and σ_yy(x, 0) = K_n U for a base slip U e^{ikx}
/// (free top), against docs/model.md §10.3's closed forms.
void inplane_static_kernels(const InPlaneStabilityParams& p, double k, std::complex<double>& kt, std::complex<double>& kn);
/// The free modes' angular frequencies ω (s = iω, ω > 0, ascending) of the frictionless base (σ̄ = η = 0): the
/// symmetric Lamb modes of docs/model.md §10.3.
std::vector<double> inplane_frictionless_frequencies(const InPlaneStabilityParams& p, double k);

}  // namespace slipfront::continuum
