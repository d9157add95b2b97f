/***************************************************************************
  camera.cpp - interior orientation of a frame camera
 ***************************************************************************/
#include "camera/camera.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>
#include <ceres/jet.h>

namespace geostation
{

  namespace
  {
    using Jet2 = ceres::Jet<double, 2>;

    /**
     * Solves model(u) = target for u (2-D) by Newton's method, starting at
     * `start`; the Jacobian comes from automatic differentiation. Returns
     * nothing when it does not converge to |residual| <= tol * max(1, |target|).
     */
    template <typename Model>
    std::optional<Eigen::Vector2d> invert2d( const Model &model, const Eigen::Vector2d &target, Eigen::Vector2d u )
    {
      const double scale = std::max( 1.0, target.norm() );
      const double tolerance = 1e-14 * scale;
      for ( int iteration = 0; iteration < 50; ++iteration )
      {
        Jet2 x( u.x(), 0 );
        Jet2 y( u.y(), 1 );
        Jet2 gx, gy;
        model( x, y, &gx, &gy );
        const Eigen::Vector2d residual( gx.a - target.x(), gy.a - target.y() );
        if ( !std::isfinite( residual.x() ) || !std::isfinite( residual.y() ) )
          return std::nullopt;
        if ( residual.norm() <= tolerance )
          return u;
        Eigen::Matrix2d jacobian;
        jacobian << gx.v[0], gx.v[1], gy.v[0], gy.v[1];
        const double det = jacobian.determinant();
        if ( !( std::abs( det ) > 1e-12 ) )
          return std::nullopt; // the model folds over here: no unique inverse
        u -= jacobian.inverse() * residual;
      }
      // Accept a solution that stalled at round-off level.
      Eigen::Vector2d g;
      model( u.x(), u.y(), &g.x(), &g.y() );
      if ( ( g - target ).norm() <= 1e-10 * scale )
        return u;
      return std::nullopt;
    }
    /**
     * Measured photo coordinates whose brown_photo correction gives `ideal`:
     * Newton's method with the analytic Jacobian of the correction (the hot
     * path of ground -> pixel for this model). Nothing if it does not converge.
     */
    std::optional<Eigen::Vector2d> invertBrownPhoto( const double *k, const Eigen::Vector2d &ideal )
    {
      const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
      const double tolerance = 1e-14 * std::max( 1.0, ideal.norm() );
      Eigen::Vector2d m = ideal; // the correction is small: start at the ideal point
      for ( int iteration = 0; iteration < 50; ++iteration )
      {
        const double x = m.x(), y = m.y(), r2 = x * x + y * y;
        const double radial = r2 * ( k1 + r2 * ( k2 + r2 * k3 ) );
        const double dRadial = k1 + r2 * ( 2.0 * k2 + 3.0 * r2 * k3 ); // dR / d(r2)
        const Eigen::Vector2d corrected( x + x * radial + p1 * ( r2 + 2.0 * x * x ) + 2.0 * p2 * x * y,
                                         y + y * radial + 2.0 * p1 * x * y + p2 * ( r2 + 2.0 * y * y ) );
        const Eigen::Vector2d residual = corrected - ideal;
        if ( !residual.allFinite() )
          return std::nullopt;
        if ( residual.norm() <= tolerance )
          return m;
        Eigen::Matrix2d jacobian;
        jacobian << 1.0 + radial + 2.0 * x * x * dRadial + 6.0 * p1 * x + 2.0 * p2 * y, 2.0 * x * y * dRadial + 2.0 * p1 * y + 2.0 * p2 * x,
                 2.0 * x * y * dRadial + 2.0 * p1 * y + 2.0 * p2 * x, 1.0 + radial + 2.0 * y * y * dRadial + 2.0 * p1 * x + 6.0 * p2 * y;
        const double det = jacobian.determinant();
        if ( !( std::abs( det ) > 1e-12 ) )
          return std::nullopt;
        const Eigen::Vector2d step( ( jacobian( 1, 1 ) * residual.x() - jacobian( 0, 1 ) * residual.y() ) / det,
                                    ( -jacobian( 1, 0 ) * residual.x() + jacobian( 0, 0 ) * residual.y() ) / det );
        m -= step;
        if ( step.norm() <= 1e-3 * tolerance )
          return m;
      }
      return std::nullopt;
    }
  } // namespace

  std::string distortionModelName( DistortionModel model )
  {
    switch ( model )
    {
      case DistortionModel::None:
        return "none";
      case DistortionModel::OpenCV:
        return "opencv";
      case DistortionModel::BrownPhoto:
        return "brown_photo";
    }
    return "none";
  }

  std::optional<DistortionModel> distortionModelFromName( const std::string &name )
  {
    if ( name == "none" )
      return DistortionModel::None;
    if ( name == "opencv" )
      return DistortionModel::OpenCV;
    if ( name == "brown_photo" )
      return DistortionModel::BrownPhoto;
    return std::nullopt;
  }

  double Camera::principalDistanceMm() const
  {
    if ( !pixelSizeMm )
      throw std::logic_error( "camera '" + id + "' has no pixel_size_mm, so its principal distance in mm is unknown" );
    return f * *pixelSizeMm;
  }

  void Camera::validate() const
  {
    const std::string who = "camera '" + id + "': ";
    if ( width <= 0 || height <= 0 )
      throw std::invalid_argument( who + "width and height must be positive pixel counts" );
    if ( !( f > 0.0 ) || !std::isfinite( f ) )
      throw std::invalid_argument( who + "principal distance f must be a positive number of pixels" );
    if ( !( aspect > 0.0 ) || !std::isfinite( aspect ) )
      throw std::invalid_argument( who + "aspect (fy/fx) must be positive" );
    if ( !std::isfinite( cx ) || !std::isfinite( cy ) )
      throw std::invalid_argument( who + "principal point cx, cy must be finite" );
    if ( pixelSizeMm && !( *pixelSizeMm > 0.0 ) )
      throw std::invalid_argument( who + "pixel_size_mm must be positive" );
    if ( distortion.model == DistortionModel::BrownPhoto && !pixelSizeMm )
      throw std::invalid_argument( who + "the brown_photo distortion model needs pixel_size_mm" );
    for ( double c : distortion.coeffs )
      if ( !std::isfinite( c ) )
        throw std::invalid_argument( who + "distortion coefficients must be finite" );
  }

  double Camera::lensFieldRadius() const
  {
    if ( distortion.model == DistortionModel::None )
      return std::numeric_limits<double>::infinity();
    double cornerRadius = 0.0;
    for ( const double col : { 0.0, static_cast<double>( width ) } )
      for ( const double row : { 0.0, static_cast<double>( height ) } )
        cornerRadius = std::max( cornerRadius, std::hypot( ( col - cx ) / fx(), ( row - cy ) / fy() ) );
    return 2.0 * cornerRadius;
  }

  bool Camera::isInFrame( const Eigen::Vector2d &pixelInImage ) const
  {
    return pixelInImage.x() >= 0.0 && pixelInImage.x() < width && pixelInImage.y() >= 0.0 && pixelInImage.y() < height;
  }

  PixelProjection Camera::pixelFromCamera( const Eigen::Vector3d &pointInCamera ) const
  {
    return pixelFromCamera( pointInCamera, lensFieldRadius() );
  }

  PixelProjection Camera::pixelFromCamera( const Eigen::Vector3d &pointInCamera, double fieldRadius ) const
  {
    PixelProjection result;
    if ( !( pointInCamera.z() < 0.0 ) )
    {
      result.status = PixelProjection::Status::BehindCamera;
      return result;
    }
    // Ideal normalised coordinates, x right, y up.
    const double xn = -pointInCamera.x() / pointInCamera.z();
    const double yn = -pointInCamera.y() / pointInCamera.z();
    if ( xn * xn + yn * yn > fieldRadius * fieldRadius )
    {
      result.status = PixelProjection::Status::OutsideLensField;
      return result;
    }

    switch ( distortion.model )
    {
      case DistortionModel::None:
        result.pixelInImage = { cx + fx() * xn, cy - fy() * yn };
        break;
      case DistortionModel::OpenCV:
      {
        // OpenCV's camera frame has y down: its normalised y is -yn.
        double xd = 0.0, yd = 0.0;
        opencvDistort( distortion.coeffs.data(), xn, -yn, &xd, &yd );
        result.pixelInImage = { cx + fx() * xd, cy + fy() * yd };
        break;
      }
      case DistortionModel::BrownPhoto:
      {
        const double ps = *pixelSizeMm;
        const double c = f * ps;
        const Eigen::Vector2d idealPhoto( c * xn, c * yn );
        const std::optional<Eigen::Vector2d> measured = invertBrownPhoto( distortion.coeffs.data(), idealPhoto );
        if ( !measured )
        {
          result.status = PixelProjection::Status::DistortionDiverged;
          return result;
        }
        result.pixelInImage = { cx + measured->x() / ps, cy - measured->y() * aspect / ps };
        break;
      }
    }
    return result;
  }

  std::optional<Eigen::Vector3d> Camera::rayInCameraFromPixel( const Eigen::Vector2d &pixelInImage ) const
  {
    switch ( distortion.model )
    {
      case DistortionModel::None:
        return Eigen::Vector3d( ( pixelInImage.x() - cx ) / fx(), -( pixelInImage.y() - cy ) / fy(), -1.0 );
      case DistortionModel::OpenCV:
      {
        const Eigen::Vector2d distorted( ( pixelInImage.x() - cx ) / fx(), ( pixelInImage.y() - cy ) / fy() );
        const double *k = distortion.coeffs.data();
        const auto model = [k]( const auto & x, const auto & y, auto * xd, auto * yd ) { opencvDistort( k, x, y, xd, yd ); };
        // Start one fixed-point step from the solution: u0 = 2 d - distort(d).
        Eigen::Vector2d twice;
        model( distorted.x(), distorted.y(), &twice.x(), &twice.y() );
        const std::optional<Eigen::Vector2d> ideal = invert2d( model, distorted, 2.0 * distorted - twice );
        if ( !ideal )
          return std::nullopt;
        return Eigen::Vector3d( ideal->x(), -ideal->y(), -1.0 );
      }
      case DistortionModel::BrownPhoto:
      {
        const double ps = *pixelSizeMm;
        const double xb = ( pixelInImage.x() - cx ) * ps;
        const double yb = -( pixelInImage.y() - cy ) * ps / aspect;
        double xi = 0.0, yi = 0.0;
        brownPhotoCorrect( distortion.coeffs.data(), xb, yb, &xi, &yi );
        const double c = f * ps;
        return Eigen::Vector3d( xi / c, yi / c, -1.0 );
      }
    }
    return std::nullopt;
  }

  std::optional<Eigen::Matrix2d> Camera::pixelJacobianWrtIdeal( const Eigen::Vector2d &pixelInImage ) const
  {
    switch ( distortion.model )
    {
      case DistortionModel::None:
        return Eigen::DiagonalMatrix<double, 2>( fx(), -fy() ).toDenseMatrix();
      case DistortionModel::OpenCV:
      {
        const std::optional<Eigen::Vector3d> ray = rayInCameraFromPixel( pixelInImage );
        if ( !ray )
          return std::nullopt;
        Jet2 x( ray->x(), 0 ), y( -ray->y(), 1 ), xd, yd;
        opencvDistort( distortion.coeffs.data(), x, y, &xd, &yd );
        Eigen::Matrix2d jacobianCv;
        jacobianCv << xd.v[0], xd.v[1], yd.v[0], yd.v[1];
        return Eigen::DiagonalMatrix<double, 2>( fx(), fy() ) * jacobianCv * Eigen::DiagonalMatrix<double, 2>( 1.0, -1.0 );
      }
      case DistortionModel::BrownPhoto:
      {
        const double ps = *pixelSizeMm;
        Jet2 xb( ( pixelInImage.x() - cx ) * ps, 0 ), yb( -( pixelInImage.y() - cy ) * ps / aspect, 1 ), xi, yi;
        brownPhotoCorrect( distortion.coeffs.data(), xb, yb, &xi, &yi );
        Eigen::Matrix2d correction;
        correction << xi.v[0], xi.v[1], yi.v[0], yi.v[1];
        if ( !( std::abs( correction.determinant() ) > 1e-12 ) )
          return std::nullopt;
        return Eigen::DiagonalMatrix<double, 2>( 1.0 / ps, -aspect / ps ) * correction.inverse() * ( f * ps );
      }
    }
    return std::nullopt;
  }

} // namespace geostation
