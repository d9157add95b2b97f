// A bundle block for speed and cancel measurements: six images of one
// pinhole camera in two strips of three, looking north level, their starts
// a little off (0.1 m, 0.02 degrees, with those sigmas), and `points`
// ground points seen in all six (0.3 px noise), the first four of them
// control. Used by bench/benchadjustment.cpp and the cancel test.
#ifndef GEOSTATION_TESTS_BUNDLESCENE_H
#define GEOSTATION_TESTS_BUNDLESCENE_H

#include <random>
#include <string>
#include <vector>

#include "adjustment/bundleadjustment.h"
#include "pinholecamera.h"

namespace geostation
{
  struct BundleScene
  {
    std::vector<Camera> cameras { centredPinhole( "bench", 1280, 960, 1100.0 ) };
    std::vector<BundleImage> images;
    std::vector<BundleObservation> observations;
    std::vector<ControlPoint> control;

    explicit BundleScene( int points )
    {
      std::mt19937 rng( 3 );
      std::normal_distribution<double> noise( 0.0, 1.0 );
      std::vector<OrientedImage> truth;
      for ( int s = 0; s < 2; ++s )
        for ( int k = 0; k < 3; ++k )
        {
          ExteriorOrientation eo; // looking north, level: omega = 90
          eo.projectionCentre = { 500000.0 + k - 1.0, 4400000.0 + 4.0 * s, 102.5 };
          eo.omegaDeg = 90.0;
          truth.emplace_back( cameras[0], eo );
          ExteriorOrientation start = eo;
          start.projectionCentre += 0.1 * Eigen::Vector3d( noise( rng ), noise( rng ), noise( rng ) );
          start.omegaDeg += 0.02 * noise( rng );
          start.sigma = ExteriorSigma { 0.1, 0.1, 0.1, 0.02, 0.02, 0.02 };
          images.push_back( { "I" + std::to_string( images.size() ), cameras[0].id, start } );
        }
      std::uniform_real_distribution<double> x( -4, 4 ), y( 14, 40 ), z( 100, 105 );
      for ( int i = 0; i < points; ++i )
      {
        const Eigen::Vector3d p( 500000.0 + x( rng ), 4400000.0 + y( rng ), z( rng ) );
        for ( size_t k = 0; k < truth.size(); ++k )
          observations.push_back( { "P" + std::to_string( i ), images[k].id, truth[k].projectGroundToPixel( p ).pixelInImage + 0.3 * Eigen::Vector2d( noise( rng ), noise( rng ) ), 0.3 } );
        if ( i < 4 )
          control.push_back( { "P" + std::to_string( i ), p, Eigen::Vector3d::Zero(), false } );
      }
    }
  };
} // namespace geostation

#endif // GEOSTATION_TESTS_BUNDLESCENE_H
