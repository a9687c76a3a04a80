#include "core/material_bake/factorisation.h"

#include <algorithm>
#include <cmath>

namespace clothbake {

void factorise(const Eigen::MatrixXf& m, float max_error, int channels, ViewFactors& out) {
  const Eigen::Index nodes = m.cols(), rows = m.rows();
  const Eigen::MatrixXd gram = (m.transpose() * m).cast<double>();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  const Eigen::VectorXd lambda = eig.eigenvalues().reverse().cwiseMax(0.0);  // descending
  const double total = lambda.sum();
  int rank = 0;
  double kept = 0.0;
  if (total > 0.0) {
    const double allowed = double(max_error) * double(max_error) * total;
    while (rank < nodes && total - kept > allowed) kept += lambda[rank++];
  }
  out.rank = rank;
  out.error = total > 0.0 ? float(std::sqrt(std::max(0.0, total - kept) / total)) : 0.0f;
  if (rank == 0) return;
  Eigen::MatrixXf v = eig.eigenvectors().rightCols(rank).rowwise().reverse().cast<float>();
  // One sign per component: the light factor sums to >= 0 (eigenvectors'
  // signs are arbitrary; this keeps them reproducible and readable).
  for (int k = 0; k < rank; ++k)
    if (v.col(k).sum() < 0.0f) v.col(k) = -v.col(k);
  const float scale = std::sqrt(float(nodes));
  const Eigen::MatrixXf u = (m * v) / scale;  // rows x rank
  v *= scale;
  const Eigen::Index texels = rows / channels;
  out.coefficients.resize(size_t(rows) * rank);
  for (Eigen::Index t = 0; t < texels; ++t)
    for (int k = 0; k < rank; ++k)
      for (int c = 0; c < channels; ++c)
        out.coefficients[(size_t(t) * rank + k) * channels + c] = u(t * channels + c, k);
  out.light.resize(size_t(nodes) * rank);
  for (Eigen::Index n = 0; n < nodes; ++n)
    for (int k = 0; k < rank; ++k) out.light[size_t(n) * rank + k] = v(n, k);
}
}  // namespace clothbake
