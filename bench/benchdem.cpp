// Ray / DEM intersection speed (targets: >= 1 M rays/s for a nadir frame,
// >= 0.3 M rays/s for a ground-level oblique photo) and ground -> image.
// In-run baseline: marching in fixed half-cell steps, then bisection.
#include <filesystem>
#include <random>

#include <benchmark/benchmark.h>

#include "benchutils.h"
#include <gdal.h>
#include <ogr_srs_api.h>

#include "dem/monoplotter.h"
#include "syntheticterrain.h"
#include "geometry/rotation.h"

using namespace geostation;

namespace
{
  using syntheticterrain::kX0;
  using syntheticterrain::kY0;
  constexpr int kCells = 2000; // 4 km x 4 km at 2 m
  double terrain( double x, double y ) { return syntheticterrain::height( x, y, 0.02 ); }

  struct Scene
  {
    std::string path;
    std::unique_ptr<Dem> dem;
    CrsTransform same { "EPSG:32633", "EPSG:32633" };
    std::vector<Ray> nadir, oblique;
    Scene()
    {
      path = syntheticterrain::tempPath( "bench-dem" );
      syntheticterrain::writeTerrain( path, kCells, kX0, "EPSG:32633", 0.02 );
      dem = std::make_unique<Dem>( path );

      Camera camera;
      camera.id = "bench";
      camera.width = 1000;
      camera.height = 1000;
      camera.f = 1000.0;
      camera.cx = camera.cy = 500.0;
      ExteriorOrientation down;
      down.projectionCentre = { kX0 + 2000.0, kY0 - 2000.0, 1100.0 };
      const OrientedImage aerial( camera, down );
      // Ground level: 1.7 m above the terrain, looking north 3 degrees down.
      ExteriorOrientation level;
      level.projectionCentre = { kX0 + 2000.0, kY0 - 3500.0, terrain( kX0 + 2000.0, kY0 - 3500.0 ) + 1.7 };
      level.omegaDeg = 87.0;
      const OrientedImage street( camera, level );
      for ( int r = 0; r < 1000; r += 4 )
        for ( int c = 0; c < 1000; c += 4 )
        {
          nadir.push_back( *aerial.worldRayFromPixel( { c + 0.5, r + 0.5 } ) );
          oblique.push_back( *street.worldRayFromPixel( { c + 0.5, 500.0 + r / 2.0 } ) ); // lower half: at the ground
        }
    }
    ~Scene() { std::filesystem::remove( path ); }
  };

  Scene &scene()
  {
    static Scene s;
    return s;
  }

  //! The baseline: fixed half-cell steps along the ray, then bisection.
  std::optional<double> fixedStep( const Ray &ray, const Dem &dem )
  {
    double previous = 0.0;
    for ( double t = 0.0; t < 20000.0; t += 1.0 )
    {
      const Eigen::Vector3d p = ray.origin + t * ray.direction;
      const std::optional<double> h = dem.heightAt( p.x(), p.y() );
      if ( !h )
        return std::nullopt;
      if ( p.z() <= *h )
      {
        double lo = previous, hi = t;
        while ( hi - lo > 1e-4 )
        {
          const double mid = 0.5 * ( lo + hi );
          const Eigen::Vector3d q = ray.origin + mid * ray.direction;
          ( q.z() > *dem.heightAt( q.x(), q.y() ) ? lo : hi ) = mid;
        }
        return lo;
      }
      previous = t;
    }
    return std::nullopt;
  }

  void run( benchmark::State &state, const std::vector<Ray> &rays, bool baseline )
  {
    Scene &s = scene();
    long hits = 0;
    for ( auto _ : state )
      for ( const Ray &ray : rays )
        hits += baseline ? fixedStep( ray, *s.dem ).has_value() : intersectRayWithDem( ray, *s.dem, s.same ).hit();
    benchmark::DoNotOptimize( hits );
    state.SetItemsProcessed( state.iterations() * rays.size() );
  }

  void BM_NadirFixedStep( benchmark::State &state ) { run( state, scene().nadir, true ); }
  void BM_NadirRayDem( benchmark::State &state ) { run( state, scene().nadir, false ); }
  void BM_ObliqueFixedStep( benchmark::State &state ) { run( state, scene().oblique, true ); }
  void BM_ObliqueRayDem( benchmark::State &state ) { run( state, scene().oblique, false ); }

} // namespace

BENCHMARK( BM_NadirFixedStep )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_NadirRayDem )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_ObliqueFixedStep )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_ObliqueRayDem )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    printf( "\nRays per second, against the fixed half-cell-step baseline of this run:\n" );
    for ( const auto &[ours, baseline, target] : { std::tuple<const char *, const char *, double> { "BM_NadirRayDem", "BM_NadirFixedStep", 1e6 },
                                                   { "BM_ObliqueRayDem", "BM_ObliqueFixedStep", 3e5 } } )
    {
      const double a = benchutils::rate( rates, ours ), b = benchutils::rate( rates, baseline );
      if ( a > 0.0 && b > 0.0 )
        printf( "  %-18s %10.3g /s  x%.1f of the baseline; target %.0e: %s\n", ours, a, a / b, target, a >= target ? "met" : "NOT met" );
    }
  } );
}
