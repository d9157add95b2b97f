/***************************************************************************
  intersection.h - space intersection of 2..N image rays, and ray / plane
  -------------------------------------------------------------------------
  Weighted least squares on the collinearity equations (thesis eq. 3.1):
  the object point minimising the pixel residuals of all rays, with its full
  covariance, normalised residuals for gross-error detection, and the
  intersection geometry.
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_INTERSECTION_H
#define GEOSTATION_ADJUSTMENT_INTERSECTION_H

#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/projection.h"

namespace geostation
{

  //! One measured image point: a pixel in an oriented image, with its precision.
  struct RayObservation
  {
    const OrientedImage *image = nullptr; //!< not owned
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    double sigmaPx = 0.5; //!< standard deviation of col and row, pixels
  };

  struct IntersectionOptions
  {
    int maxIterations = 20;
    double convergenceM = 1e-9;        //!< stop when the update is smaller (metres)
    double minRayAngleDeg = 0.05;      //!< rays closer to parallel are refused
    double grossErrorThreshold = 4.0;  //!< normalised residual (Baarda's w) that flags a gross error
    /**
     * Scale the covariance by the a posteriori variance factor sigma0^2.
     * Off by default: with few rays sigma0 is itself too uncertain, so the
     * covariance follows from the given pixel sigmas (sigma0 = 1).
     */
    bool scaleCovarianceBySigma0 = false;
  };

  struct RayResidual
  {
    Eigen::Vector2d residualPx = Eigen::Vector2d::Zero(); //!< projected - observed (col, row)
    double normalised = 0.0; //!< largest |w| of its two components
    bool suspect = false;    //!< the ray most likely to carry a gross error (needs >= 3 rays)
    double rangeM = 0.0;     //!< distance from the projection centre to the point
  };

  struct IntersectionSummary
  {
    enum class Status
    {
      Ok,
      TooFewRays,    //!< fewer than two observations
      RayUndefined,  //!< a pixel whose ray the lens model cannot give
      ParallelRays,  //!< largest ray angle below minRayAngleDeg
      BehindCamera,  //!< the rays meet behind one of the cameras
      NotConverged,
    };
    Status status = Status::Ok;
    std::string message; //!< one sentence when not ok

    Eigen::Vector3d point = Eigen::Vector3d::Zero();           //!< block CRS, metres
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();      //!< m^2
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();          //!< sqrt of the diagonal
    int iterations = 0;
    int redundancy = 0;          //!< 2 n - 3
    double sigma0 = 0.0;         //!< a posteriori, relative to the given pixel sigmas
    double rmsPx = 0.0;
    double maxResidualPx = 0.0;
    double maxRayAngleDeg = 0.0; //!< the intersection geometry: largest angle between two rays
    bool grossError = false;     //!< some |w| exceeds the threshold
    std::vector<RayResidual> residuals; //!< one per observation, in input order

    bool ok() const { return status == Status::Ok; }
  };

  /**
   * Intersects the rays of two or more observations.
   * Throws std::invalid_argument for an observation without image or with a
   * non-positive sigma; expected failures are reported in the status.
   */
  IntersectionSummary intersectRays( const std::vector<RayObservation> &observations, const IntersectionOptions &options = IntersectionOptions() );

  /**
   * A per-point status name for batch outputs: "ok", "too_few_rays",
   * "ray_undefined", "parallel_rays", "behind_camera", "no_solution" (not
   * converged).
   */
  std::string intersectionStatusName( IntersectionSummary::Status status );

  //! A plane n . X = offset (n need not be unit length).
  struct Plane
  {
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    double offset = 0.0;

    //! The horizontal plane Z = heightM (e.g. the road under a survey van).
    static Plane horizontal( double heightM ) { return Plane { Eigen::Vector3d::UnitZ(), heightM }; }
  };

  struct PlaneIntersectionSummary
  {
    enum class Status
    {
      Ok,
      RayUndefined,
      ParallelToPlane,
      BehindCamera, //!< the plane is behind the camera along this ray
    };
    Status status = Status::Ok;
    std::string message;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero(); //!< from pixel and plane sigmas, m^2
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    double rangeM = 0.0;
    double incidenceDeg = 0.0; //!< angle between ray and plane; small = grazing, weak

    bool ok() const { return status == Status::Ok; }
  };

  /**
   * Intersects one observation's ray with a plane, propagating the pixel sigma
   * and the plane's position sigma (along its normal, metres).
   */
  PlaneIntersectionSummary intersectRayWithPlane( const RayObservation &observation, const Plane &plane, double planeSigmaM = 0.0 );

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_INTERSECTION_H
