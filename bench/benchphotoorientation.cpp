// The orientation dock's live resection (issue 18): every change of the
// control list solves the photo again with Baarda's data snooping
// (orientPhoto()). Target: a change is answered within 50 ms, so the dock
// keeps up with clicks, up to 400 points. Baseline in the same run: the
// core resection of the same points (resectImage(), which removes blunders
// too); the ratio is what the dock's bookkeeping adds (every point's
// prediction in file pixels, residuals, w, ground errors of flagged points).
//
// The scene: an oblique photo (1024 x 768, f 1000 px) 300 m above rolling
// ground, looking 40 degrees down; control points spread over the view,
// measured with 0.5 px noise, one of them a 15 px blunder.
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include <benchmark/benchmark.h>

#include "benchutils.h"

#include "adjustment/resection.h"
#include "geometry/projection.h"
#include "workstation/photoorientation.h"
#include "pinholecamera.h"

using namespace geostation;

namespace
{
  Camera photoCamera() { return centredPinhole( "photo", 1024, 768, 1000.0 ); }

  struct PhotoScene
  {
    Camera camera = photoCamera();
    ExteriorOrientation truth;
    std::vector<PhotoControlPoint> points;
    std::vector<ControlPoint> control;
    std::vector<ImagePoint> observations;

    explicit PhotoScene( int count )
    {
      truth.projectionCentre = Eigen::Vector3d( 500000.0, 5400000.0, 400.0 );
      truth.omegaDeg = 50.0; // looking north, 40 degrees down
      const OrientedImage image( camera, truth );
      std::mt19937 rng( 7 );
      std::uniform_real_distribution<double> col( 20.0, 1004.0 ), row( 20.0, 748.0 );
      std::normal_distribution<double> noise( 0.0, 0.5 );
      while ( static_cast<int>( points.size() ) < count )
      {
        // a pixel's ray down to the rolling ground (100 m +- 8 m): the point, then its measurement
        const std::optional<Ray> ray = image.worldRayFromPixel( Eigen::Vector2d( col( rng ), row( rng ) ) );
        if ( !ray || ray->direction.z() > -0.05 )
          continue;
        double t = ( truth.projectionCentre.z() - 100.0 ) / -ray->direction.z();
        Eigen::Vector3d world = ray->origin + t * ray->direction;
        world.z() = 100.0 + 8.0 * std::sin( world.x() / 90.0 ) * std::cos( world.y() / 70.0 );
        const GroundProjection g = image.projectGroundToPixel( world );
        if ( !g.ok() || !g.inFrame )
          continue;
        PhotoControlPoint p;
        p.pointId = "P" + std::to_string( points.size() );
        p.world = world;
        p.pixelInFile = g.pixelInImage + Eigen::Vector2d( noise( rng ), noise( rng ) );
        if ( points.size() == 3 )
          *p.pixelInFile += Eigen::Vector2d( 12.0, -9.0 ); // the blunder
        points.push_back( p );
        control.push_back( { p.pointId, p.world, Eigen::Vector3d::Zero(), false } );
        observations.push_back( { p.pointId, *p.pixelInFile, 0.5 } );
      }
    }
  };

  const PhotoScene &scene( int count )
  {
    static std::map<int, PhotoScene> scenes;
    if ( !scenes.count( count ) )
      scenes.emplace( count, PhotoScene( count ) );
    return scenes.at( count );
  }

  void BM_ResectImage( benchmark::State &state )
  {
    const PhotoScene &s = scene( static_cast<int>( state.range( 0 ) ) );
    for ( auto _ : state )
    {
      const ResectionSummary r = resectImage( s.camera, s.control, s.observations );
      if ( !r.ok() )
        state.SkipWithError( r.message.c_str() );
      benchmark::DoNotOptimize( r.sigma0 );
    }
    state.SetItemsProcessed( state.iterations() );
  }

  void BM_OrientPhoto( benchmark::State &state )
  {
    const PhotoScene &s = scene( static_cast<int>( state.range( 0 ) ) );
    bool flagged = false;
    double centreErrorM = 0.0;
    for ( auto _ : state )
    {
      const PhotoOrientationSummary r = orientPhoto( s.camera, std::nullopt, s.points );
      if ( !r.oriented() )
      {
        state.SkipWithError( r.message.c_str() );
        break;
      }
      flagged = r.points[3].blunder;
      centreErrorM = ( r.resection.exterior.projectionCentre - s.truth.projectionCentre ).norm();
    }
    // the answer itself: the blunder flagged, the camera where it is
    state.counters["blunder_flagged"] = flagged ? 1 : 0;
    state.counters["centre_error_m"] = centreErrorM;
    state.SetItemsProcessed( state.iterations() );
  }
} // namespace

BENCHMARK( BM_ResectImage )->Arg( 12 )->Arg( 50 )->Arg( 400 )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_OrientPhoto )->Arg( 12 )->Arg( 50 )->Arg( 400 )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    printf( "\nThe dock's live resection (one change of the control list), against the core resection of the same points:\n" );
    for ( const int n : { 12, 50, 400 } )
    {
      const double live = benchutils::rate( rates, "BM_OrientPhoto/" + std::to_string( n ) ), plain = benchutils::rate( rates, "BM_ResectImage/" + std::to_string( n ) );
      if ( live > 0.0 && plain > 0.0 )
        printf( "  %3d points: %7.2f ms a change (%.2f times the core resection's %.2f ms); target <= 50 ms: %s\n", n, 1e3 / live, plain / live, 1e3 / plain,
                1e3 / live <= 50.0 ? "met" : "NOT met" );
    }
  } );
}
