// Ray / DEM intersection speed (targets: >= 1 M rays/s for a nadir frame,
// >= 0.3 M rays/s for a ground-level oblique photo) and ground -> image.
// In-run baselines: marching in fixed half-cell steps, then bisection; and
// GDAL's DEM-backed RPC transformer (RPC_DEM) on the same pixels, with an RPC
// fitted to the camera.
#include <filesystem>
#include <map>
#include <random>

#include <benchmark/benchmark.h>

#include "benchutils.h"
#include <gdal.h>
#include <ogr_srs_api.h>

#include "dem/monoplotter.h"
#include "syntheticterrain.h"
#include "geometry/rotation.h"
#include "rpcfit.h"
#include <gdal_alg.h>

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
    //! Numerically the same coordinates, but another CRS: the ray is followed chord by chord.
    CrsTransform other { "EPSG:32633", "EPSG:25833" };
    std::vector<Ray> nadir, oblique;
    std::vector<Eigen::Vector2d> nadirPixels, obliquePixels;
    GDALRPCInfoV2 nadirRpc {}, obliqueRpc {};
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
          nadirPixels.emplace_back( c + 0.5, r + 0.5 );
          obliquePixels.emplace_back( c + 0.5, 500.0 + r / 2.0 ); // lower half: at the ground
          nadir.push_back( *aerial.worldRayFromPixel( nadirPixels.back() ) );
          oblique.push_back( *street.worldRayFromPixel( obliquePixels.back() ) );
        }
      // RPCs fitted to points along a grid of rays, over the depths where the ground is
      const CrsTransform toWgs84( "EPSG:32633", "EPSG:4326" );
      for ( const auto &[image, rpc, near, far] : { std::tuple<const OrientedImage *, GDALRPCInfoV2 *, double, double> { &aerial, &nadirRpc, 900.0, 1200.0 },
                                                    { &street, &obliqueRpc, 2.0, 4000.0 } } )
      {
        std::vector<Eigen::Vector3d> ground;
        for ( int r = 0; r <= 1000; r += 50 )
          for ( int c = 0; c <= 1000; c += 50 )
          {
            const Ray ray = *image->worldRayFromPixel( { static_cast<double>( c ), static_cast<double>( r ) } );
            for ( int k = 0; k <= 12; ++k )
              ground.push_back( ray.origin + near * std::pow( far / near, k / 12.0 ) * ray.direction );
          }
        *rpc = rpcfit::fit( *image, ground, toWgs84 );
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

  void run( benchmark::State &state, const std::vector<Ray> &rays, bool baseline, bool otherCrs = false )
  {
    Scene &s = scene();
    long hits = 0, steps = 0;
    for ( auto _ : state )
      for ( const Ray &ray : rays )
      {
        if ( baseline )
          hits += fixedStep( ray, *s.dem ).has_value();
        else
        {
          const DemIntersection hit = intersectRayWithDem( ray, *s.dem, otherCrs ? s.other : s.same );
          hits += hit.hit();
          steps += hit.steps;
        }
      }
    benchmark::DoNotOptimize( hits );
    state.SetItemsProcessed( state.iterations() * rays.size() );
    state.counters["success"] = static_cast<double>( hits ) / ( state.iterations() * rays.size() );
    if ( !baseline )
      state.counters["steps"] = static_cast<double>( steps ) / ( state.iterations() * rays.size() );
  }

  //! Share of the rays GDAL returned a point for, per benchmark.
  std::map<std::string, double> &gdalSuccess()
  {
    static std::map<std::string, double> success;
    return success;
  }

  //! GDAL's RPC transformer with RPC_DEM: pixel -> ground on the DEM, on every 8th pixel.
  void runGdal( benchmark::State &state, const char *name, const std::vector<Eigen::Vector2d> &pixels, const GDALRPCInfoV2 &rpc )
  {
    Scene &s = scene();
    const std::string demOption = "RPC_DEM=" + s.path;
    const char *options[] = { demOption.c_str(), "RPC_DEM_INTERPOLATION=bilinear", nullptr };
    // pixel error threshold 0.001 px: about 1 mm on the ground, the accuracy ray / DEM delivers
    void *transformer = GDALCreateRPCTransformerV2( &rpc, FALSE, 0.001, const_cast<char **>( options ) );
    if ( !transformer )
    {
      state.SkipWithError( "GDAL cannot create the RPC transformer" );
      return;
    }
    std::vector<double> x, y, z;
    std::vector<int> ok;
    long hits = 0;
    for ( auto _ : state )
    {
      x.clear();
      y.clear();
      for ( size_t i = 0; i < pixels.size(); i += 8 )
      {
        x.push_back( pixels[i].x() - 0.5 );
        y.push_back( pixels[i].y() - 0.5 );
      }
      z.assign( x.size(), 0.0 );
      ok.assign( x.size(), 0 );
      GDALRPCTransform( transformer, FALSE, static_cast<int>( x.size() ), x.data(), y.data(), z.data(), ok.data() );
      for ( int v : ok )
        hits += v;
    }
    GDALDestroyRPCTransformer( transformer );
    benchmark::DoNotOptimize( hits );
    state.SetItemsProcessed( state.iterations() * ( ( pixels.size() + 7 ) / 8 ) );
    state.counters["success"] = static_cast<double>( hits ) / ( state.iterations() * ( ( pixels.size() + 7 ) / 8 ) );
    gdalSuccess()[name] = state.counters["success"];
  }

  void BM_NadirGdalRpcDem( benchmark::State &state ) { runGdal( state, "BM_NadirGdalRpcDem", scene().nadirPixels, scene().nadirRpc ); }
  void BM_ObliqueGdalRpcDem( benchmark::State &state ) { runGdal( state, "BM_ObliqueGdalRpcDem", scene().obliquePixels, scene().obliqueRpc ); }
  void BM_NadirFixedStep( benchmark::State &state ) { run( state, scene().nadir, true ); }
  void BM_NadirRayDem( benchmark::State &state ) { run( state, scene().nadir, false ); }
  void BM_NadirOtherCrs( benchmark::State &state ) { run( state, scene().nadir, false, true ); }
  void BM_ObliqueFixedStep( benchmark::State &state ) { run( state, scene().oblique, true ); }
  void BM_ObliqueRayDem( benchmark::State &state ) { run( state, scene().oblique, false ); }

} // namespace

BENCHMARK( BM_NadirGdalRpcDem )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_ObliqueGdalRpcDem )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_NadirFixedStep )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_NadirRayDem )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_NadirOtherCrs )->Unit( benchmark::kMillisecond );
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
    const double other = benchutils::rate( rates, "BM_NadirOtherCrs" ), fixed = benchutils::rate( rates, "BM_NadirFixedStep" );
    if ( other > 0.0 && fixed > 0.0 )
      printf( "  %-18s %10.3g /s  x%.1f of the baseline (a DEM in another CRS: chords through PROJ)\n", "BM_NadirOtherCrs", other, other / fixed );
    printf( "\nAgainst GDAL's DEM-backed RPC transformer (RPC_DEM, bilinear) on the same pixels (target x20), one core each:\n" );
    for ( const auto &[ours, gdal] : { std::pair<const char *, const char *> { "BM_NadirRayDem", "BM_NadirGdalRpcDem" }, { "BM_ObliqueRayDem", "BM_ObliqueGdalRpcDem" } } )
    {
      const double a = benchutils::rate( rates, ours ), b = benchutils::rate( rates, gdal );
      const auto success = gdalSuccess().find( gdal );
      if ( a <= 0.0 || b <= 0.0 || success == gdalSuccess().end() )
        continue;
      if ( success->second < 0.5 )
        printf( "  %-18s %10.3g /s  GDAL returns a point for only %.0f %% of these rays (its height iteration fails on them): no rate to compare\n", ours, a, 100.0 * success->second );
      else
        printf( "  %-18s %10.3g /s  GDAL %10.3g /s (a point for %.0f %% of the rays)  x%.1f: %s\n", ours, a, b, 100.0 * success->second, a / b, a / b >= 20.0 ? "met" : "NOT met" );
    }
  } );
}
