#pragma once
// What the fronts of the bodies of finite height share across their height (docs/fronts.md §10.2, §10.3, §11.3):
// the graded rows y_j, the far-field subspaces (the left eigenspace of the modes a front must not contain at
// ξ = −L or ahead of the tip) and the interpolation of a column of row values. Used by the antiplane strip
// (continuum/strip_front.cpp) and the in-plane strip (continuum/inplane_front.cpp), with the interface's rows of their
// node blocks (the law behind the tip, the tip conditions, the far-field rows with their c and σ_d columns) and the
// status of a converged front. Internal to continuum/; no I/O.
#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "continuum/front_solver.hpp"
#include "core/params.hpp"

namespace slipfront::continuum::far_field {

/// Rows graded toward the interface: y_j = H (e^{γ j/M} − 1)/(e^γ − 1); γ = `grading` if > 0, else from the first
/// spacing `first` (TOMS 748); uniform (γ = 0) when H/M ≤ first.
double row_grading_of(double H, int M, double first, double grading);
std::vector<double> make_rows(double H, int M, double g);
/// The spacings k_j = y_{j+1} − y_j and the dual widths w_j of rows y (half cells on both faces), docs/fronts.md §10.2.
void row_widths(const std::vector<double>& y, std::vector<double>& k, std::vector<double>& w);

/// The far-field conditions (docs/fronts.md §10.3): the modes a front must not contain (behind: those that decay in
/// forward ξ, growing toward −∞; ahead: those that grow with ξ), as an orthonormal basis Q of their left eigenspace.
struct Subspace {
  Eigen::MatrixXd Q;          ///< columns: orthonormal basis of the excluded modes' left eigenspace
  std::vector<std::complex<double>> excluded, kept;  ///< eigenvalues, sorted by real part
  bool ok = false;
  std::string why;
};

/// The left eigenspace of the `count` eigenvalues of Jr with the smallest (lowest = true) or largest real parts;
/// not ok unless they are separated from the others by the imaginary axis (allow_null: the last may be 0, the
/// saddle-node's null mode).
Subspace left_subspace(const Eigen::MatrixXd& Jr, int count, bool lowest, bool allow_null);

/// Linear interpolation of a column of row values `col` on rows `yo` at yy, continued above the old top with slope
/// `top_slope`.
double interp_rows(const std::vector<double>& yo, const double* col, double yy, double top_slope);

/// T: y → z, dropping the first unknown (u_0: the translation u → u + const of the sliding state behind), n × n → (n − 1) × n.
Eigen::MatrixXd translation_free(int n);

/// Where the interface's unknowns sit in a node's state: A, σ̄, the slip u_0 and its ξ-derivative p_0 (v = −c p_0).
struct InterfaceIndex {
  int A, S, u0, p0;
};

/// The law behind the tip (docs/fronts.md eq. 1b, 1c) into the rows A, S of r (f, fc and, with the Jacobian, J):
/// A' = −(1 − A − κA|v|)/c, σ̄' = −(αAv − σ̄|v|)/c, v = −c p_0; fc the total c-derivative at fixed p_0.
template <class Rhs, class Vec>
void interface_law_rows(const core::InterfaceParams& law, const Vec& y, double c, InterfaceIndex ix, bool with_jacobian,
                        Rhs& r) {
  const double p0 = y[ix.p0], v = -c * p0, A = y[ix.A], s = y[ix.S];
  const double speed = std::abs(v), sign = v >= 0.0 ? 1.0 : -1.0;
  const double relax = 1.0 - A - law.kappa * A * speed, source = law.alpha * A * v - s * speed;
  r.f[ix.A] = -relax / c;
  r.f[ix.S] = -source / c;
  const double dA_dv = law.kappa * A * sign / c, dS_dv = -(law.alpha * A - s * sign) / c;
  r.fc[ix.A] = relax / (c * c) + dA_dv * (-p0);
  r.fc[ix.S] = source / (c * c) + dS_dv * (-p0);
  if (!with_jacobian) return;
  r.J(ix.A, ix.A) = (1.0 + law.kappa * speed) / c;
  r.J(ix.A, ix.p0) = dA_dv * (-c);
  r.J(ix.S, ix.A) = -law.alpha * v / c;
  r.J(ix.S, ix.S) = speed / c;
  r.J(ix.S, ix.p0) = dS_dv * (-c);
}

/// The three tip conditions at rows r2 … r2 + 2 (Θ switches at ξ = 0): A = 1, σ̄ = α u_0, σ̄ + η v = 1; the node's
/// state yN at column `base`.
void tip_law_rows(const Eigen::VectorXd& yN, int r2, int base, double c, const core::InterfaceParams& law,
                  InterfaceIndex ix, front_solver::Rows& rows, front_solver::ScalarColumns col);

/// Far-field rows at `row` from proj(y, c, σ_d, G*) (its value; G: its y-derivative, block at column `base`), their c
/// column a central difference (step 1e-6 c) and, with σ_d free, their σ_d column one (step hs).
template <class Proj>
void projection_rows(int row, int base, const Eigen::VectorXd& y, double c, double sd, double hs, front_solver::Rows& rows,
                     front_solver::ScalarColumns col, Proj&& proj) {
  Eigen::MatrixXd G;
  const Eigen::VectorXd F = proj(y, c, sd, rows.jacobian() ? &G : nullptr);
  rows.F.segment(row, F.size()) = F;
  if (!rows.jacobian()) return;
  rows.block(row, base, G);
  const double hc = 1e-6 * c;
  rows.column(row, col.c, (proj(y, c + hc, sd, nullptr) - proj(y, c - hc, sd, nullptr)) / (2.0 * hc));
  if (col.free_sigma()) rows.column(row, col.sigma, (proj(y, c, sd + hs, nullptr) - proj(y, c, sd - hs, nullptr)) / (2.0 * hs));
}

/// The status of a converged front from its diagnostics: reverse_slip (min v ≤ 0), resticks (|σ|/A − 1 ≤ 0 behind the
/// tip), else converged (docs/fronts.md §4).
template <class Front>
void classify(Front& f) {
  f.status = FrontStatus::converged;
  f.reason.clear();
  if (f.min_slip_rate <= 0.0) {
    f.status = FrontStatus::reverse_slip;
    f.reason = "v <= 0 behind the tip (min v = " + core::format_number(f.min_slip_rate) + ")";
  } else if (f.overstress_margin <= 0.0) {
    f.status = FrontStatus::resticks;
    f.reason = "|sigma|/A - 1 <= 0 behind the tip (min " + core::format_number(f.overstress_margin) + "): Theta = 1 violated";
  }
}

}  // namespace slipfront::continuum::far_field
