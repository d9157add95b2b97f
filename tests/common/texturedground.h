// A real photograph lying on a ground surface (a plane, or a DEM) and the
// images oriented cameras take of it: each pixel's ray meets the surface and
// the photograph is sampled there (bicubic), then sensor noise and 8-bit
// quantisation. The truth of a conjugate point is the reference pixel's
// ground point projected into the other image. A scene built differently
// from the simulator's (another texture, surface model and sampling), for
// matching tests and benchmarks on real image content.
#ifndef GEOSTATION_TESTS_TEXTUREDGROUND_H
#define GEOSTATION_TESTS_TEXTUREDGROUND_H

#include <cmath>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "camera/camera.h"
#include "geometry/projection.h"
#include "geometry/rotation.h"
#include "geometry/windowshape.h"

namespace texturedground
{
  using namespace geostation;

  const std::string kData = "/usr/share/doc/opencv-doc/examples/data/";

  inline Camera frameCamera( int width, int height, double f )
  {
    Camera c;
    c.id = "cam";
    c.width = width;
    c.height = height;
    c.f = f;
    c.cx = width / 2.0;
    c.cy = height / 2.0;
    return c;
  }

  /**
   * A camera at `centre` looking along azimuth `azimuthDeg` (clockwise from
   * +Y, north) and `depressionDeg` below the horizon, image rows upright.
   */
  inline OrientedImage lookingAt( const Camera &camera, const Eigen::Vector3d &centre, double azimuthDeg, double depressionDeg )
  {
    // omega = 90 - depression looks north; the world turn about Z gives the azimuth
    const Eigen::Matrix3d north = worldFromCameraRotationDeg( 90.0 - depressionDeg, 0.0, 0.0 );
    const double a = degToRad( -azimuthDeg );
    Eigen::Matrix3d turn;
    turn << std::cos( a ), -std::sin( a ), 0, std::sin( a ), std::cos( a ), 0, 0, 0, 1;
    return OrientedImage( camera, ExteriorOrientation::fromCentreAndRotation( centre, turn * north ) );
  }

  //! A grey photograph lying on the ground: its top-left corner at (x0, y0), `groundPerPixel` metres per pixel, rows to the south.
  struct GroundTexture
  {
    cv::Mat grey; //!< CV_32F
    double x0 = 0.0, y0 = 0.0, groundPerPixel = 0.02;

    bool covers( const Eigen::Vector3d &p, double marginPx ) const
    {
      const double u = ( p.x() - x0 ) / groundPerPixel, v = ( y0 - p.y() ) / groundPerPixel;
      return u > marginPx && v > marginPx && u < grey.cols - marginPx && v < grey.rows - marginPx;
    }
  };

  inline GroundTexture texture( const std::string &name, double groundPerPixel, const Eigen::Vector2d &centreXY )
  {
    GroundTexture t;
    cv::Mat grey = cv::imread( kData + name, cv::IMREAD_GRAYSCALE );
    if ( grey.empty() )
      return t;
    grey.convertTo( t.grey, CV_32F );
    t.groundPerPixel = groundPerPixel;
    t.x0 = centreXY.x() - grey.cols * groundPerPixel / 2.0;
    t.y0 = centreXY.y() + grey.rows * groundPerPixel / 2.0;
    return t;
  }

  /**
   * The image a camera takes of the textured surface: each pixel's ray meets
   * the surface, the photograph is sampled there (bicubic; outside it, mid
   * grey), then sensor noise (sd 2 grey values) and 8-bit quantisation.
   */
  inline cv::Mat render( const OrientedImage &image, const GroundTexture &t, const GroundOfPixel &surface, unsigned seed )
  {
    const Camera &c = image.camera();
    cv::Mat mapU( c.height, c.width, CV_32F, cv::Scalar( -1e4 ) ), mapV( c.height, c.width, CV_32F, cv::Scalar( -1e4 ) );
    for ( int r = 0; r < c.height; ++r )
      for ( int col = 0; col < c.width; ++col )
        if ( const std::optional<Eigen::Vector3d> g = surface( image, Eigen::Vector2d( col + 0.5, r + 0.5 ) ) )
        {
          // OpenCV's remap samples with pixel centres at integers
          mapU.at<float>( r, col ) = static_cast<float>( ( g->x() - t.x0 ) / t.groundPerPixel - 0.5 );
          mapV.at<float>( r, col ) = static_cast<float>( ( t.y0 - g->y() ) / t.groundPerPixel - 0.5 );
        }
    cv::Mat out;
    cv::remap( t.grey, out, mapU, mapV, cv::INTER_CUBIC, cv::BORDER_CONSTANT, cv::Scalar( 128 ) );
    cv::Mat noise( out.size(), CV_32F );
    cv::RNG rng( seed );
    rng.fill( noise, cv::RNG::NORMAL, 0.0, 2.0 );
    out += noise;
    cv::Mat grey8;
    out.convertTo( grey8, CV_8U );
    return grey8;
  }

  inline GroundOfPixel groundPlane( double heightM )
  {
    return [heightM]( const OrientedImage &image, const Eigen::Vector2d &pixel ) { return roadPlanePoint( image, pixel, heightM ); };
  }
}

#endif
