/***************************************************************************
  paintedpair.h - a vertical aerial pair over painted fields, rendered
  independently of the survey simulator
  -------------------------------------------------------------------------
  Two vertical photos with one camera model for both (lens model none),
  85 % forward overlap, 0.3 m ground pixels over level terrain at 120 m:
  fields 60 x 45 m of their own brightness, and in each either crop rows
  of its own direction and spacing with soil and plants that do not repeat
  ("rows"), or stripes that repeat the same way in every field ("repeating":
  a texture whose aliases line up everywhere). Each pixel is the field's
  grey where its ray meets the ground, with noise of 2 grey levels.
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_PAINTEDPAIR_H
#define GEOSTATION_TESTS_PAINTEDPAIR_H

#include <cmath>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "camera/camera.h"
#include "geometry/projection.h"

namespace geostation::paintedpair
{
  enum class Texture
  {
    Rows,
    Repeating,
  };

  struct PaintedPair
  {
    Camera camera;
    std::vector<ExteriorOrientation> exterior; //!< A, B
    std::vector<cv::Mat> grey;                 //!< A, B
    double terrainM = 120.0;
  };

  inline double hashUnit( long a, long b, unsigned salt )
  {
    unsigned h = static_cast<unsigned>( a * 73856093L ^ b * 19349663L ^ salt * 83492791u );
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return ( h % 10000 ) / 10000.0;
  }

  inline double fieldGrey( double x, double y, Texture texture )
  {
    if ( std::abs( y - 20.0 ) < 4.0 )
      return 100.0; // a road east-west
    if ( std::abs( x - 35.0 ) < 3.0 )
      return 95.0; // and one north-south
    const long i = static_cast<long>( std::floor( x / 60.0 ) ), j = static_cast<long>( std::floor( y / 45.0 ) );
    if ( texture == Texture::Repeating )
    {
      const unsigned h = static_cast<unsigned>( i * 73856093u ^ j * 19349663u );
      return 60.0 + ( h % 150 ) + 10.0 * std::sin( ( x * ( 1 + ( h % 5 ) ) + y * ( ( h >> 3 ) % 3 ) ) * 1.7 ) + 6.0 * std::sin( x * 0.37 + y * 0.91 + ( h % 7 ) );
    }
    const double angle = M_PI * hashUnit( i, j, 2 ), spacing = 1.5 + 4.0 * hashUnit( i, j, 3 );
    const double rows = 12.0 * std::sin( ( x * std::cos( angle ) + y * std::sin( angle ) ) * 2.0 * M_PI / spacing );
    const double speck = 14.0 * ( hashUnit( static_cast<long>( std::floor( x / 0.6 ) ), static_cast<long>( std::floor( y / 0.6 ) ), 4 ) - 0.5 );
    return 60.0 + 150.0 * hashUnit( i, j, 1 ) + rows + speck;
  }

  //! A camera without distortion, `width` x 3/4 width pixels, its focal length `width` pixels, its principal point in the middle.
  inline Camera paintedCamera( int width, double pixelSizeMm )
  {
    Camera camera;
    camera.id = "one";
    camera.width = width;
    camera.height = width * 3 / 4;
    camera.f = width;
    camera.cx = width / 2.0;
    camera.cy = camera.height / 2.0;
    camera.pixelSizeMm = pixelSizeMm;
    return camera;
  }

  //! The pair at `width` x 3/4 width pixels.
  inline PaintedPair paintedPair( int width, Texture texture, uint32_t seed = 3 )
  {
    PaintedPair pair;
    const int height = width * 3 / 4;
    const double gsd = 0.3;
    pair.camera = paintedCamera( width, 0.005 );
    const Camera &camera = pair.camera;
    const double flyingM = pair.terrainM + camera.f * gsd;
    for ( int k = 0; k < 2; ++k )
    {
      ExteriorOrientation e;
      e.projectionCentre = Eigen::Vector3d( k * 0.15 * width * gsd, 0.0, flyingM );
      e.omegaDeg = 0.3 * k;
      e.phiDeg = -0.2;
      e.kappaDeg = 0.5 * k;
      pair.exterior.push_back( e );
    }
    std::mt19937 random( seed );
    std::normal_distribution<double> noise( 0.0, 2.0 );
    for ( int k = 0; k < 2; ++k )
    {
      const OrientedImage image( camera, pair.exterior[k] );
      cv::Mat grey( height, width, CV_8U );
      for ( int r = 0; r < height; ++r )
        for ( int c = 0; c < width; ++c )
        {
          const std::optional<Ray> ray = image.worldRayFromPixel( Eigen::Vector2d( c + 0.5, r + 0.5 ) );
          const Eigen::Vector3d g = ray->origin + ( pair.terrainM - ray->origin.z() ) / ray->direction.z() * ray->direction;
          grey.at<uint8_t>( r, c ) = cv::saturate_cast<uint8_t>( fieldGrey( g.x(), g.y(), texture ) + noise( random ) );
        }
      pair.grey.push_back( grey );
    }
    return pair;
  }

} // namespace geostation::paintedpair

#endif // GEOSTATION_TESTS_PAINTEDPAIR_H
