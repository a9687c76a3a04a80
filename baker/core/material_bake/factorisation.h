#pragma once
/// Step 3 of the material bake (material_bake.h): one view node's texels x
/// channels by light-node matrix factorised to the smallest rank whose
/// relative error meets the settings' max_error.

#include <vector>

#include <Eigen/Dense>

namespace clothbake {

/// One view node's factorised table at level 0, before the layout's
/// largest rank is known.
struct ViewFactors {
  int rank = 0;
  float error = 0.0f;
  std::vector<float> coefficients;  ///< [texel * rank + k] * channels + c
  std::vector<float> light;         ///< [node * rank + k]
  std::vector<float> alpha;         ///< [texel]
};

/// The truncated SVD of m (rows: texels x `channels`, columns: light nodes)
/// through its Gram matrix m^T m, whose eigenvectors are the right singular
/// vectors: cheaper than an SVD of the tall matrix (one product of rows x
/// nodes^2, then an eigensolve of nodes x nodes) and exact to double
/// precision in the solve. Keeps the smallest rank whose relative Frobenius
/// error is at most `max_error`. Scaled so that the light factor's entries
/// are of order 1 and the coefficients of order of a radiance. Fills `out`'s
/// rank, error, coefficients and light factors; leaves its alpha.
void factorise(const Eigen::MatrixXf& m, float max_error, int channels, ViewFactors& out);

}  // namespace clothbake
