// A flat road at Z = 100 with one painted stripe along Y at X = 2.5 m
// (0.15 m wide), rendered into oriented images with 2 x 2 samples a pixel
// and grey noise: a scene built here, not by the simulator, for the
// tracing tests. Which parts of the stripe carry paint is the caller's
// (worn paint).
#ifndef GEOSTATION_TESTS_STRIPEDROAD_H
#define GEOSTATION_TESTS_STRIPEDROAD_H

#include <cmath>
#include <functional>
#include <optional>
#include <random>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "camera/camera.h"
#include "geometry/projection.h"
#include "pinholecamera.h"

namespace stripedroad
{
  using namespace geostation;

  constexpr double kRoadZ = 100.0, kStripeX = 2.5, kStripeHalfWidth = 0.075;

  //! A van camera: 800 x 600 px, f = 700 px, no distortion.
  inline Camera vanCamera()
  {
    Camera c = centredPinhole( "pair", 800, 600, 700.0 );
    c.pixelSizeMm = 0.0074;
    return c;
  }

  //! The point of the road a pixel sees; nothing above the horizon.
  inline std::optional<Eigen::Vector3d> onRoad( const OrientedImage &image, const Eigen::Vector2d &pixel )
  {
    const std::optional<Ray> ray = image.worldRayFromPixel( pixel );
    if ( !ray || ray->direction.z() > -1e-6 )
      return std::nullopt;
    return Eigen::Vector3d( ray->origin + ( kRoadZ - ray->origin.z() ) / ray->direction.z() * ray->direction );
  }

  //! The whole stripe painted.
  inline bool fullStripe( double x, double ) { return std::abs( x - kStripeX ) < kStripeHalfWidth; }

  //! Paint (200) where `paintAt(x, y)`, asphalt (60) elsewhere on the road, sky (90) above the horizon; Gaussian noise.
  inline cv::Mat render( const OrientedImage &image, const std::function<bool( double, double )> &paintAt, double noiseSigma, std::mt19937 &rng )
  {
    std::normal_distribution<double> noise( 0.0, noiseSigma );
    cv::Mat grey( image.camera().height, image.camera().width, CV_8UC1 );
    for ( int r = 0; r < grey.rows; ++r )
      for ( int c = 0; c < grey.cols; ++c )
      {
        double sum = 0.0;
        for ( const double dr : { 0.25, 0.75 } )
          for ( const double dc : { 0.25, 0.75 } )
          {
            double value = 90.0;
            if ( const std::optional<Eigen::Vector3d> p = onRoad( image, Eigen::Vector2d( c + dc, r + dr ) ) )
              value = paintAt( p->x(), p->y() ) ? 200.0 : 60.0;
            sum += 0.25 * value;
          }
        grey.at<uchar>( r, c ) = cv::saturate_cast<uchar>( sum + noise( rng ) );
      }
    return grey;
  }
}

#endif // GEOSTATION_TESTS_STRIPEDROAD_H
