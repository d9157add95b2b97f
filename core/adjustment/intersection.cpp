/***************************************************************************
  intersection.cpp - space intersection of 2..N image rays, and ray / plane
  -------------------------------------------------------------------------
  Each observation is turned once into ideal normalised coordinates (the lens
  model inverted) and the local Jacobian J = d(pixel)/d(ideal). The Gauss-
  Newton iterations then use the undistorted collinearity equations, with
  residuals J (ideal_projected - ideal_observed) / sigma, which equal the
  pixel residuals to first order: exact weights at pinhole speed.
 ***************************************************************************/
#include "adjustment/intersection.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "geometry/rotation.h"

namespace geostation
{

  namespace
  {
    struct PreparedRay
    {
      const OrientedImage *image;
      Eigen::Vector2d ideal;       //!< observed ideal normalised coordinates (y up)
      Eigen::Matrix2d whitening;   //!< J / sigma: ideal -> whitened pixel residual
      Ray ray;
    };

    IntersectionSummary failure( IntersectionSummary::Status status, const std::string &message )
    {
      IntersectionSummary summary;
      summary.status = status;
      summary.message = message;
      return summary;
    }

    double angleDeg( const Eigen::Vector3d &a, const Eigen::Vector3d &b )
    {
      return radToDeg( std::atan2( a.cross( b ).norm(), a.dot( b ) ) );
    }
  } // namespace

  std::string intersectionStatusName( IntersectionSummary::Status status )
  {
    switch ( status )
    {
      case IntersectionSummary::Status::Ok:
        return "ok";
      case IntersectionSummary::Status::TooFewRays:
        return "too_few_rays";
      case IntersectionSummary::Status::RayUndefined:
        return "ray_undefined";
      case IntersectionSummary::Status::ParallelRays:
        return "parallel_rays";
      case IntersectionSummary::Status::BehindCamera:
        return "behind_camera";
      case IntersectionSummary::Status::NotConverged:
        return "no_solution";
    }
    return "no_solution";
  }

  IntersectionSummary intersectRays( const std::vector<RayObservation> &observations, const IntersectionOptions &options )
  {
    for ( const RayObservation &o : observations )
    {
      if ( !o.image )
        throw std::invalid_argument( "intersectRays: an observation has no image" );
      if ( !( o.sigmaPx > 0.0 ) )
        throw std::invalid_argument( "intersectRays: pixel sigma must be positive" );
    }
    const int n = static_cast<int>( observations.size() );
    if ( n < 2 )
      return failure( IntersectionSummary::Status::TooFewRays, "an intersection needs the point in at least two images" );

    std::vector<PreparedRay> rays;
    rays.reserve( n );
    for ( int i = 0; i < n; ++i )
    {
      const RayObservation &o = observations[i];
      const Camera &camera = o.image->camera();
      const std::optional<Eigen::Vector3d> rayInCamera = camera.rayInCameraFromPixel( o.pixelInImage );
      const std::optional<Eigen::Matrix2d> jacobian = camera.pixelJacobianWrtIdeal( o.pixelInImage );
      const std::optional<Ray> ray = o.image->worldRayFromPixel( o.pixelInImage );
      if ( !rayInCamera || !jacobian || !ray )
        return failure( IntersectionSummary::Status::RayUndefined, "observation " + std::to_string( i + 1 ) + " lies where the lens model of camera '" + camera.id + "' cannot be inverted" );
      rays.push_back( { o.image, rayInCamera->head<2>(), *jacobian / o.sigmaPx, *ray } );
    }

    IntersectionSummary summary;
    for ( int i = 0; i < n; ++i )
      for ( int j = i + 1; j < n; ++j )
        summary.maxRayAngleDeg = std::max( summary.maxRayAngleDeg, angleDeg( rays[i].ray.direction, rays[j].ray.direction ) );
    if ( summary.maxRayAngleDeg < options.minRayAngleDeg )
    {
      std::ostringstream message;
      message << "the rays are nearly parallel (largest angle " << summary.maxRayAngleDeg << " degrees); measure the point in images further apart";
      return failure( IntersectionSummary::Status::ParallelRays, message.str() );
    }

    // Start: the point closest to all rays.
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for ( const PreparedRay &r : rays )
    {
      const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - r.ray.direction * r.ray.direction.transpose();
      A += projector;
      b += projector * r.ray.origin;
    }
    Eigen::Vector3d point = A.ldlt().solve( b );

    Eigen::Matrix3d normal;
    for ( summary.iterations = 1; summary.iterations <= options.maxIterations; ++summary.iterations )
    {
      normal.setZero();
      Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
      for ( size_t i = 0; i < rays.size(); ++i )
      {
        const PreparedRay &r = rays[i];
        const Eigen::Vector3d p = r.image->cameraFromWorld( point );
        if ( !( p.z() < 0.0 ) )
          return failure( IntersectionSummary::Status::BehindCamera, "the rays meet behind the camera of observation " + std::to_string( i + 1 ) + " (camera '" + r.image->camera().id + "'); check the point identification" );
        const double iz = 1.0 / p.z();
        const Eigen::Vector2d projected( -p.x() * iz, -p.y() * iz );
        Eigen::Matrix<double, 2, 3> dIdealDp;
        dIdealDp << -iz, 0.0, p.x() * iz * iz, 0.0, -iz, p.y() * iz * iz;
        const Eigen::Matrix<double, 2, 3> a = r.whitening * dIdealDp * r.image->cameraFromWorldRotation();
        const Eigen::Vector2d residual = r.whitening * ( projected - r.ideal );
        normal += a.transpose() * a;
        gradient += a.transpose() * residual;
      }
      const Eigen::Vector3d step = -normal.ldlt().solve( gradient );
      if ( !step.allFinite() )
        return failure( IntersectionSummary::Status::ParallelRays, "the intersection geometry is degenerate" );
      point += step;
      if ( step.norm() < options.convergenceM )
        break;
    }
    if ( summary.iterations > options.maxIterations )
      return failure( IntersectionSummary::Status::NotConverged, "the intersection did not converge in " + std::to_string( options.maxIterations ) + " iterations" );

    // Final residuals, covariance and normalised residuals at the solution.
    Eigen::MatrixXd design( 2 * n, 3 );
    Eigen::VectorXd whitened( 2 * n );
    normal.setZero();
    for ( int i = 0; i < n; ++i )
    {
      const PreparedRay &r = rays[i];
      const Eigen::Vector3d p = r.image->cameraFromWorld( point );
      if ( !( p.z() < 0.0 ) )
        return failure( IntersectionSummary::Status::BehindCamera, "the rays meet behind the camera of observation " + std::to_string( i + 1 ) );
      const double iz = 1.0 / p.z();
      Eigen::Matrix<double, 2, 3> dIdealDp;
      dIdealDp << -iz, 0.0, p.x() * iz * iz, 0.0, -iz, p.y() * iz * iz;
      design.block<2, 3>( 2 * i, 0 ) = r.whitening * dIdealDp * r.image->cameraFromWorldRotation();
      whitened.segment<2>( 2 * i ) = r.whitening * ( Eigen::Vector2d( -p.x() * iz, -p.y() * iz ) - r.ideal );
    }
    normal = design.transpose() * design;
    const Eigen::Matrix3d cofactor = normal.inverse();
    summary.redundancy = 2 * n - 3;
    summary.sigma0 = summary.redundancy > 0 ? std::sqrt( whitened.squaredNorm() / summary.redundancy ) : 0.0;
    summary.covariance = cofactor;
    if ( options.scaleCovarianceBySigma0 && summary.redundancy > 0 )
      summary.covariance *= summary.sigma0 * summary.sigma0;
    summary.sigmaM = summary.covariance.diagonal().cwiseSqrt();
    summary.point = point;

    // Baarda's w: residual over its own standard deviation, Q_vv = I - A N^-1 A^T.
    const Eigen::VectorXd qvv = ( Eigen::MatrixXd::Identity( 2 * n, 2 * n ) - design * cofactor * design.transpose() ).diagonal();
    double sumSquaresPx = 0.0;
    int worst = -1;
    double worstW = 0.0;
    summary.residuals.resize( n );
    for ( int i = 0; i < n; ++i )
    {
      RayResidual &res = summary.residuals[i];
      const GroundProjection exact = rays[i].image->projectGroundToPixel( point );
      res.residualPx = exact.ok() ? Eigen::Vector2d( exact.pixelInImage - observations[i].pixelInImage )
                       : Eigen::Vector2d( whitened.segment<2>( 2 * i ) * observations[i].sigmaPx );
      res.rangeM = ( point - rays[i].ray.origin ).norm();
      for ( int k = 0; k < 2; ++k )
      {
        const double q = qvv( 2 * i + k );
        if ( q > 1e-12 )
          res.normalised = std::max( res.normalised, std::abs( whitened( 2 * i + k ) ) / std::sqrt( q ) );
      }
      sumSquaresPx += res.residualPx.squaredNorm();
      summary.maxResidualPx = std::max( summary.maxResidualPx, res.residualPx.norm() );
      if ( res.normalised > worstW )
      {
        worstW = res.normalised;
        worst = i;
      }
    }
    summary.rmsPx = std::sqrt( sumSquaresPx / ( 2.0 * n ) );
    summary.grossError = worstW > options.grossErrorThreshold;
    // With two rays the residuals cannot say which ray is wrong.
    if ( summary.grossError && summary.redundancy >= 3 && worst >= 0 )
      summary.residuals[worst].suspect = true;
    return summary;
  }

  PlaneIntersectionSummary intersectRayWithPlane( const RayObservation &observation, const Plane &plane, double planeSigmaM )
  {
    if ( !observation.image )
      throw std::invalid_argument( "intersectRayWithPlane: the observation has no image" );
    if ( !( observation.sigmaPx >= 0.0 ) || !( planeSigmaM >= 0.0 ) || !( plane.normal.norm() > 0.0 ) )
      throw std::invalid_argument( "intersectRayWithPlane: sigmas must be non-negative and the plane normal non-zero" );

    PlaneIntersectionSummary summary;
    const Camera &camera = observation.image->camera();
    const std::optional<Eigen::Vector3d> rayInCamera = camera.rayInCameraFromPixel( observation.pixelInImage );
    const std::optional<Eigen::Matrix2d> jacobian = camera.pixelJacobianWrtIdeal( observation.pixelInImage );
    if ( !rayInCamera || !jacobian )
    {
      summary.status = PlaneIntersectionSummary::Status::RayUndefined;
      summary.message = "the pixel lies where the lens model of camera '" + camera.id + "' cannot be inverted";
      return summary;
    }
    const Eigen::Matrix3d worldFromCamera = observation.image->cameraFromWorldRotation().transpose();
    const Eigen::Vector3d origin = observation.image->exterior().projectionCentre;
    const Eigen::Vector3d d = worldFromCamera * *rayInCamera; // not unit: (xn, yn, -1) rotated
    const Eigen::Vector3d n = plane.normal;
    const double nd = n.dot( d );
    summary.incidenceDeg = radToDeg( std::asin( std::min( 1.0, std::abs( nd ) / ( n.norm() * d.norm() ) ) ) );
    if ( std::abs( nd ) < 1e-12 * n.norm() * d.norm() )
    {
      summary.status = PlaneIntersectionSummary::Status::ParallelToPlane;
      summary.message = "the ray runs parallel to the plane";
      return summary;
    }
    const double t = ( plane.offset - n.dot( origin ) ) / nd;
    if ( !( t > 0.0 ) )
    {
      summary.status = PlaneIntersectionSummary::Status::BehindCamera;
      summary.message = "the plane lies behind the camera along this ray";
      return summary;
    }
    summary.point = origin + t * d;
    summary.rangeM = ( summary.point - origin ).norm();

    // X = o + d (h - n.o) / (n.d): dX/dd = t (I - d n^T / (n.d)), dd/d(ideal) = R[:, 0:2],
    // d(ideal)/d(pixel) = J^-1; dX/dh = d / (n.d).
    const Eigen::Matrix3d dXdd = t * ( Eigen::Matrix3d::Identity() - d * n.transpose() / nd );
    const Eigen::Matrix<double, 3, 2> dXdPixel = dXdd * worldFromCamera.leftCols<2>() * jacobian->inverse();
    const Eigen::Vector3d dXdh = d / nd;
    summary.covariance = observation.sigmaPx * observation.sigmaPx * dXdPixel * dXdPixel.transpose() + planeSigmaM * planeSigmaM * dXdh * dXdh.transpose();
    summary.sigmaM = summary.covariance.diagonal().cwiseSqrt();
    return summary;
  }

} // namespace geostation
