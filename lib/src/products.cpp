#include "sparsempm/products.hpp"

#include "sparsempm/errors.hpp"

#include "kernels.hpp"

#include <string>

namespace smpm {

namespace {

// C is the number of dense columns when known at compile time (0: run-time c).
template <int C>
void multiply_rows(const SparseRowMatrix& A, const Field& X, Field& Y, int c) {
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* val = A.valuePtr();
  const int cols = C ? C : c;
  for (Index p = 0; p < A.rows(); ++p) {
    double acc[C ? C : 16] = {};
    for (int k = outer[p]; k < outer[p + 1]; ++k) {
      const double* x = X.data() + Index(inner[k]) * cols;
      for (int a = 0; a < cols; ++a)
        acc[a] += val[k] * x[a];
    }
    double* y = Y.data() + p * cols;
    for (int a = 0; a < cols; ++a)
      y[a] = acc[a];
  }
}

template <int C>
void multiply_rows_transpose(const SparseRowMatrix& A, const Field& X, Field& Y, int c) {
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* val = A.valuePtr();
  const int cols = C ? C : c;
  Y.setZero();
  for (Index p = 0; p < A.rows(); ++p) {
    const double* x = X.data() + p * cols;
    for (int k = outer[p]; k < outer[p + 1]; ++k) {
      double* y = Y.data() + Index(inner[k]) * cols;
      for (int a = 0; a < cols; ++a)
        y[a] += val[k] * x[a];
    }
  }
}

// Compile-time column counts for the common widths, run-time (0) otherwise.
template <class Kernel>
void dispatch(int c, Kernel&& k) {
  if (!detail::dispatch_int<1, 2, 3, 4, 6>(c, k))
    k.template operator()<0>();
}

void check_pattern(const std::array<SparseRowMatrix, 3>& G, int d) {
  for (int b = 1; b < d; ++b)
    if (G[b].nonZeros() != G[0].nonZeros() || G[b].rows() != G[0].rows())
      throw InputError("gradient matrices G_b must share one sparsity pattern");
}

template <int D>
void gradient_rows(const std::array<SparseRowMatrix, 3>& G, const Field& v, Field& L) {
  const int* outer = G[0].outerIndexPtr();
  const int* inner = G[0].innerIndexPtr();
  const double* g[3] = {G[0].valuePtr(), D > 1 ? G[1].valuePtr() : nullptr,
                        D > 2 ? G[2].valuePtr() : nullptr};
  for (Index p = 0; p < G[0].rows(); ++p) {
    double acc[D * D] = {};
    for (int k = outer[p]; k < outer[p + 1]; ++k) {
      const double* vi = v.data() + Index(inner[k]) * D;
      for (int b = 0; b < D; ++b) {
        const double gb = g[b][k];
        for (int a = 0; a < D; ++a)
          acc[a * D + b] += vi[a] * gb;
      }
    }
    double* l = L.data() + p * D * D;
    for (int q = 0; q < D * D; ++q)
      l[q] = acc[q];
  }
}

template <int D>
void divergence_rows(const std::array<SparseRowMatrix, 3>& G, const Field& T, Field& f) {
  const int* outer = G[0].outerIndexPtr();
  const int* inner = G[0].innerIndexPtr();
  const double* g[3] = {G[0].valuePtr(), D > 1 ? G[1].valuePtr() : nullptr,
                        D > 2 ? G[2].valuePtr() : nullptr};
  f.setZero();
  for (Index p = 0; p < G[0].rows(); ++p) {
    const double* t = T.data() + p * D * D;
    for (int k = outer[p]; k < outer[p + 1]; ++k) {
      double* fi = f.data() + Index(inner[k]) * D;
      for (int a = 0; a < D; ++a) {
        double s = 0;
        for (int b = 0; b < D; ++b)
          s += t[a * D + b] * g[b][k];
        fi[a] += s;
      }
    }
  }
}

} // namespace

void multiply(const SparseRowMatrix& A, const Field& X, Field& Y) {
  if (X.rows() != A.cols())
    throw InputError("multiply: A is " + std::to_string(A.rows()) + " x " +
                     std::to_string(A.cols()) + " but X has " + std::to_string(X.rows()) + " rows");
  const int c = int(X.cols());
  Y.resize(A.rows(), c);
  if (c > 16) {
    Y.noalias() = A * X;
    return;
  }
  dispatch(c, [&]<int C>() { multiply_rows<C>(A, X, Y, c); });
}

void multiply_transpose(const SparseRowMatrix& A, const Field& X, Field& Y) {
  if (X.rows() != A.rows())
    throw InputError("multiply_transpose: A is " + std::to_string(A.rows()) + " x " +
                     std::to_string(A.cols()) + " but X has " + std::to_string(X.rows()) + " rows");
  const int c = int(X.cols());
  Y.resize(A.cols(), c);
  dispatch(c, [&]<int C>() { multiply_rows_transpose<C>(A, X, Y, c); });
}

void gradient_product(const std::array<SparseRowMatrix, 3>& G, int d, const Field& v, Field& L) {
  check_pattern(G, d);
  if (v.rows() != G[0].cols() || v.cols() != d)
    throw InputError("gradient_product: v must be n x d");
  L.resize(G[0].rows(), d * d);
  switch (d) {
  case 1:
    gradient_rows<1>(G, v, L);
    break;
  case 2:
    gradient_rows<2>(G, v, L);
    break;
  default:
    gradient_rows<3>(G, v, L);
    break;
  }
}

void divergence_product(const std::array<SparseRowMatrix, 3>& G, int d, const Field& T, Field& f) {
  check_pattern(G, d);
  if (T.rows() != G[0].rows() || T.cols() != d * d)
    throw InputError("divergence_product: T must be N x d^2");
  f.resize(G[0].cols(), d);
  switch (d) {
  case 1:
    divergence_rows<1>(G, T, f);
    break;
  case 2:
    divergence_rows<2>(G, T, f);
    break;
  default:
    divergence_rows<3>(G, T, f);
    break;
  }
}

} // namespace smpm
