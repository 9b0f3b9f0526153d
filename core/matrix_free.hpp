#pragma once
// What the bodies' fast solves share (core/strip.cpp, core/inplane.cpp): a matrix-free operator and its
// preconditioner as Eigen sees them (Eigen docs, "Matrix-free solvers"), for Eigen's iterative solvers
// (ConjugateGradient, MINRES), and the one mutex under which every FFTW plan of the process is made and destroyed.
//
// The operator is any object `op` with
//   op.apply_system(x, y)           y = A x (const double* x, double* y; the vectors have the size given)
//   op.apply_preconditioner(r)      z = P⁻¹ r, returned as a pointer to size values held by op
// MatrixFree<Op> (Op may be const) is A; MatrixFreePreconditioner<Op> is P⁻¹ for the solver's template argument:
//   const MatrixFree<const Strip> A(*this, dofs());
//   Eigen::ConjugateGradient<MatrixFree<const Strip>, Eigen::Lower | Eigen::Upper, MatrixFreePreconditioner<const Strip>> cg;
// Eigen's CG asks for tmp = A p and for rhs − A x (into a temporary): both are evalTo, written directly into the
// destination; a scaled product goes through a temporary.
#include <cstddef>
#include <mutex>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace slipfront::core {

/// FFTW's planner (and fftw_destroy_plan) is not thread-safe; fftw_execute is. Every plan of the process is made
/// and destroyed under this mutex (core/matrix_free.cpp).
std::mutex& fftw_planner_mutex();

template <class Op>
class MatrixFree;

}  // namespace slipfront::core

namespace Eigen::internal {
template <class Op>
struct traits<slipfront::core::MatrixFree<Op>> : public traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace slipfront::core {

template <class Op>
class MatrixFree : public Eigen::EigenBase<MatrixFree<Op>> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = false };

  MatrixFree(Op& op, std::size_t size) : op_(&op), n_(static_cast<Eigen::Index>(size)) {}
  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return n_; }
  template <class Rhs>
  Eigen::Product<MatrixFree, Rhs, Eigen::AliasFreeProduct> operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<MatrixFree, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }
  Op& op() const { return *op_; }

 private:
  Op* op_;
  Eigen::Index n_;
};

template <class Op>
class MatrixFreePreconditioner {
 public:
  MatrixFreePreconditioner() = default;
  template <class M>
  explicit MatrixFreePreconditioner(const M& m) { compute(m); }
  MatrixFreePreconditioner& analyzePattern(const MatrixFree<Op>&) { return *this; }
  MatrixFreePreconditioner& factorize(const MatrixFree<Op>& m) { return compute(m); }
  MatrixFreePreconditioner& compute(const MatrixFree<Op>& m) {
    op_ = &m.op();
    return *this;
  }
  template <class Rhs>
  Eigen::Map<const Eigen::VectorXd> solve(const Eigen::MatrixBase<Rhs>& r) const {
    const Eigen::Ref<const Eigen::VectorXd> rr(r.derived());
    return Eigen::Map<const Eigen::VectorXd>(op_->apply_preconditioner(rr.data()), rr.size());
  }
  Eigen::ComputationInfo info() const { return Eigen::Success; }

 private:
  Op* op_ = nullptr;
};

}  // namespace slipfront::core

namespace Eigen::internal {
template <class Op, class Rhs>
struct generic_product_impl<slipfront::core::MatrixFree<Op>, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<slipfront::core::MatrixFree<Op>, Rhs,
                                generic_product_impl<slipfront::core::MatrixFree<Op>, Rhs>> {
  using Scalar = typename Product<slipfront::core::MatrixFree<Op>, Rhs>::Scalar;
  template <class Dest>
  static void evalTo(Dest& dst, const slipfront::core::MatrixFree<Op>& lhs, const Rhs& rhs) {
    const Eigen::Ref<const Eigen::VectorXd> x(rhs);
    Eigen::Ref<Eigen::VectorXd> y(dst);
    lhs.op().apply_system(x.data(), y.data());
  }
  template <class Dest>
  static void scaleAndAddTo(Dest& dst, const slipfront::core::MatrixFree<Op>& lhs, const Rhs& rhs, const Scalar& alpha) {
    Eigen::VectorXd tmp(dst.size());
    evalTo(tmp, lhs, rhs);
    dst += alpha * tmp;
  }
};
}  // namespace Eigen::internal
