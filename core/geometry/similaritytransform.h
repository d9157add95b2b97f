/***************************************************************************
  similaritytransform.h - seven-parameter similarity (Helmert) transform
  -------------------------------------------------------------------------
  target = scale * rotation * source + translation. Fitted in closed form
  (Umeyama 1991, least squares over all point pairs) to bring a model in an
  arbitrary frame (structure from motion) into the block CRS from known
  camera centres or control points, with the residuals of every pair.
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_SIMILARITYTRANSFORM_H
#define GEOSTATION_GEOMETRY_SIMILARITYTRANSFORM_H

#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/exteriororientation.h"

namespace geostation
{

  struct SimilarityTransform
  {
    double scale = 1.0;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity(); //!< proper rotation (det +1)
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();

    Eigen::Vector3d apply( const Eigen::Vector3d &pointInSource ) const { return scale * ( rotation * pointInSource ) + translation; }

    /**
     * An exterior orientation given in the source frame, in the target frame:
     * the centre transformed, the attitude rotated; a priori sigmas dropped
     * (they belonged to the source frame).
     */
    ExteriorOrientation apply( const ExteriorOrientation &exteriorInSource ) const;

    SimilarityTransform inverse() const;
  };

  //! One pair of the fit: its name, the transformed source point and the residual target - transformed.
  struct SimilarityPairResidual
  {
    std::string name;
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    Eigen::Vector3d residualM = Eigen::Vector3d::Zero(); //!< target minus transformed source, target units
  };

  struct SimilarityFitSummary
  {
    SimilarityTransform targetFromSource;
    std::vector<SimilarityPairResidual> residuals; //!< in the order of the pairs given
    double rmsM = 0.0;   //!< 3-D RMS of the residuals, target units
    double maxM = 0.0;   //!< largest 3-D residual
    /**
     * How far the known points spread off their best-fitting line: the
     * second singular value of the centred points over the first (the
     * smaller of source and target). Below about 0.05 (a straight strip of
     * camera centres) the rotation about that line is weakly determined.
     */
    double spreadRatio = 0.0;
    //! Standard deviation of one coordinate, sqrt(sum |r|^2 / (3n - 7)), target units
    double sigma0M = 0.0;
  };

  /**
   * Least-squares similarity from at least three non-collinear pairs.
   * `names` (optional, same length) label the residuals. Throws
   * std::invalid_argument with one sentence for fewer than three pairs,
   * mismatched lengths, non-finite coordinates, or (near-)collinear points
   * (the rotation about their line would be undetermined).
   */
  SimilarityFitSummary fitSimilarityTransform( const std::vector<Eigen::Vector3d> &source, const std::vector<Eigen::Vector3d> &target,
      const std::vector<std::string> &names = {} );

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_SIMILARITYTRANSFORM_H
