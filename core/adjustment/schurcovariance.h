/***************************************************************************
  schurcovariance.h - marginal covariances of a bundle-structured problem
  -------------------------------------------------------------------------
  With the parameters split into a few "camera" blocks (poses, interiors)
  and many small "point" blocks, the normal matrix is
      N = [ U  W ; W^T  V ],  V block diagonal.
  The reduced camera system S = U - W V^-1 W^T is small; then
      Cov(cameras) = S^-1
      Cov(point j) = V_j^-1 + V_j^-1 W_j^T S^-1 W_j V_j^-1
  which is what a surveyor needs (per-image and per-point precision) at a
  cost linear in the number of points, instead of a full inverse.
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_SCHURCOVARIANCE_H
#define GEOSTATION_ADJUSTMENT_SCHURCOVARIANCE_H

#include <vector>

#include <Eigen/Core>

namespace ceres
{
  class Problem;
}

namespace geostation
{

  struct SchurCovariance
  {
    bool ok = false; //!< false when the normal matrix is singular
    Eigen::MatrixXd cameras;             //!< over all camera blocks' tangent spaces, in the given order
    std::vector<int> cameraOffsets;      //!< first column of each camera block in `cameras`
    std::vector<Eigen::MatrixXd> points; //!< one per point block, its tangent space
  };

  /**
   * Unscaled covariances (the inverse normal matrix, sigma0 = 1) of the free
   * parameter blocks of a problem, evaluated without loss functions. Blocks
   * are given by their data pointers; constant blocks must not be listed.
   * Each point block must appear in no residual together with another point.
   */
  SchurCovariance schurCovariance( ceres::Problem &problem, const std::vector<double *> &cameraBlocks, const std::vector<double *> &pointBlocks );

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_SCHURCOVARIANCE_H
