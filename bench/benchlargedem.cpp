// Ray / DEM intersection on a large DEM streamed from disk: a 20 000 x
// 20 000 cell GeoTIFF (1 m cells, 20 km square, tiled 256 x 256, DEFLATE,
// about 0.9 GB) written once into the temporary folder, never loaded
// whole. Nadir rays from 1100 m and grazing rays from a camera 1.7 m above
// the ground looking 3 degrees down (rays that cross kilometres of DEM and
// hundreds of its tiles), each ray answered from a freshly opened DEM (cold:
// every tile read from disk) and again (warm). Baseline in the same run: the
// same rays on a 2000 x 2000 part of the same terrain. Prints time per ray,
// tiles read and memory: the process's resident set before and after, the
// DEM's own tile cache and GDAL's block cache.
//
// Not part of the test suite (writing the DEM takes about a minute):
//   build/bench/geostation_bench_large_dem [--benchmark_min_time=...]
// GEOSTATION_LARGE_DEM_CELLS=N changes the size (default 20000).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include "benchutils.h"
#include "dem/demintersection.h"
#include "syntheticterrain.h"

using namespace geostation;

namespace
{
  using syntheticterrain::kX0;
  using syntheticterrain::kY0;
  //! Rolling hills (25 m over about 2-3 km) with small bumps: rays from near the ground cross kilometres.
  double terrain( double x, double y )
  {
    return 100.0 + 25.0 * std::sin( ( x - kX0 ) / 700.0 ) * std::cos( ( y - kY0 ) / 900.0 ) + 2.0 * std::sin( ( x - kX0 ) / 40.0 ) * std::cos( ( y - kY0 ) / 55.0 );
  }

  //! Resident set and its peak (VmRSS, VmHWM) in MB.
  std::pair<double, double> residentMb()
  {
    std::ifstream status( "/proc/self/status" );
    std::string key;
    double rss = 0.0, peak = 0.0;
    while ( status >> key )
    {
      double kb = 0.0;
      if ( key == "VmRSS:" && status >> kb )
        rss = kb / 1024.0;
      else if ( key == "VmHWM:" && status >> kb )
        peak = kb / 1024.0;
    }
    return { rss, peak };
  }

  //! A tiled, compressed Float32 GeoTIFF of `cells` x `cells` at 1 m, written strip by strip.
  void writeTiledTerrain( const std::string &path, int cells )
  {
    GDALAllRegister();
    const char *options[] = { "TILED=YES", "BLOCKXSIZE=256", "BLOCKYSIZE=256", "COMPRESS=DEFLATE", "PREDICTOR=3", "ZLEVEL=1", "BIGTIFF=IF_SAFER", nullptr };
    GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), path.c_str(), cells, cells, 1, GDT_Float32, const_cast<char **>( options ) );
    if ( !ds )
      throw std::runtime_error( "cannot create " + path );
    double gt[6] = { kX0, 1.0, 0.0, kY0, 0.0, -1.0 };
    GDALSetGeoTransform( ds, gt );
    OGRSpatialReferenceH srs = OSRNewSpatialReference( nullptr );
    OSRSetFromUserInput( srs, "EPSG:32633" );
    GDALSetSpatialRef( ds, srs );
    OSRDestroySpatialReference( srs );
    const int strip = 256;
    std::vector<float> values( static_cast<size_t>( cells ) * strip );
    for ( int r0 = 0; r0 < cells; r0 += strip )
    {
      const int rows = std::min( strip, cells - r0 );
      for ( int r = 0; r < rows; ++r )
        for ( int c = 0; c < cells; ++c )
          values[static_cast<size_t>( r ) * cells + c] = static_cast<float>( terrain( kX0 + c + 0.5, kY0 - ( r0 + r ) - 0.5 ) );
      if ( GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Write, 0, r0, cells, rows, values.data(), cells, rows, GDT_Float32, 0, 0 ) != CE_None )
        throw std::runtime_error( "cannot write " + path );
    }
    GDALClose( ds );
  }

  struct LargeScene
  {
    int cells = 20000;
    std::string large, small;
    CrsTransform same { "EPSG:32633", "EPSG:32633" };
    std::vector<Ray> nadirLarge, grazingLarge, nadirSmall, grazingSmall;
    LargeScene()
    {
      if ( const char *n = std::getenv( "GEOSTATION_LARGE_DEM_CELLS" ) )
        cells = std::max( 2000, std::atoi( n ) );
      large = syntheticterrain::tempPath( "bench-large-dem" );
      small = syntheticterrain::tempPath( "bench-large-dem-baseline" );
      const auto t0 = std::chrono::steady_clock::now();
      writeTiledTerrain( large, cells );
      const double seconds = std::chrono::duration<double>( std::chrono::steady_clock::now() - t0 ).count();
      writeTiledTerrain( small, 2000 );
      std::printf( "DEM of %d x %d cells (1 m) written in %.0f s, %.0f MB on disk\n", cells, cells, seconds, std::filesystem::file_size( large ) / 1e6 );
      // the cameras over the middle of each DEM: rays every 4th pixel of a 1000 x 1000 frame (f = 1000 px)
      for ( const auto &[half, nadir, grazing] : { std::tuple<double, std::vector<Ray> *, std::vector<Ray> *> { cells / 2.0, &nadirLarge, &grazingLarge },
                                                   { 1000.0, &nadirSmall, &grazingSmall } } )
      {
        Camera camera;
        camera.id = "bench";
        camera.width = camera.height = 1000;
        camera.f = 1000.0;
        camera.cx = camera.cy = 500.0;
        ExteriorOrientation down, level;
        down.projectionCentre = { kX0 + half, kY0 - half, 1100.0 };
        // grazing: 1.7 m above the ground, 900 m south of the middle, looking north 3 degrees down; the rows
        // from the horizon (447.6) to 568: rays 0.02-3.4 degrees below the horizontal, tens of metres to kilometres long
        level.projectionCentre = { kX0 + half, kY0 - half - 900.0, terrain( kX0 + half, kY0 - half - 900.0 ) + 1.7 };
        level.omegaDeg = 87.0;
        const OrientedImage aerial( camera, down ), street( camera, level );
        for ( int r = 0; r < 1000; r += 4 )
          for ( int c = 0; c < 1000; c += 4 )
          {
            nadir->push_back( *aerial.worldRayFromPixel( { c + 0.5, r + 0.5 } ) );
            grazing->push_back( *street.worldRayFromPixel( { c + 0.5, 448.0 + 0.12 * r } ) );
          }
      }
    }
    ~LargeScene()
    {
      std::filesystem::remove( large );
      std::filesystem::remove( small );
    }
  };

  LargeScene &scene()
  {
    static LargeScene s;
    return s;
  }

  //! Every ray intersected with a freshly opened DEM (cold) or the one opened before (warm).
  void run( benchmark::State &state, const std::string &path, const std::vector<Ray> &rays, bool cold, size_t cacheTiles = DemOptions().cacheTiles )
  {
    DemOptions options;
    options.cacheTiles = cacheTiles;
    const LargeScene &s = scene();
    const std::pair<double, double> before = residentMb();
    std::unique_ptr<Dem> dem;
    long hits = 0, steps = 0, tileReads = 0;
    for ( auto _ : state )
    {
      if ( cold || !dem )
      {
        state.PauseTiming();
        dem.reset();
        while ( GDALFlushCacheBlock() ) // GDAL's block cache emptied too: every tile from disk
          ;
        dem = std::make_unique<Dem>( path, options );
        if ( !cold ) // warm: one pass first, untimed, so the caches hold what they will hold
          for ( const Ray &ray : rays )
            intersectRayWithDem( ray, *dem, s.same );
        state.ResumeTiming();
      }
      const long readsBefore = dem->tileReadCount();
      for ( const Ray &ray : rays )
      {
        const DemIntersection hit = intersectRayWithDem( ray, *dem, s.same );
        hits += hit.hit();
        steps += hit.steps;
      }
      tileReads += dem->tileReadCount() - readsBefore;
    }
    const std::pair<double, double> after = residentMb();
    const double tileMb = options.cacheTiles * ( ( options.tileSize + 1.0 ) * ( options.tileSize + 1.0 ) * 4.0 ) / 1e6;
    state.SetItemsProcessed( state.iterations() * rays.size() );
    state.counters["success"] = static_cast<double>( hits ) / ( state.iterations() * rays.size() );
    state.counters["tiles_read_per_kray"] = 1000.0 * tileReads / ( state.iterations() * rays.size() );
    state.counters["steps"] = static_cast<double>( steps ) / ( state.iterations() * rays.size() );
    state.counters["rss_MB"] = after.first;
    state.counters["rss_growth_MB"] = after.first - before.first;
    state.counters["peak_MB"] = after.second;
    state.counters["tile_cache_MB"] = tileMb;
    state.counters["gdal_cache_MB"] = static_cast<double>( GDALGetCacheUsed64() ) / 1e6;
  }

  void BM_SmallNadirCold( benchmark::State &state ) { run( state, scene().small, scene().nadirSmall, true ); }
  void BM_LargeNadirCold( benchmark::State &state ) { run( state, scene().large, scene().nadirLarge, true ); }
  void BM_SmallGrazingCold( benchmark::State &state ) { run( state, scene().small, scene().grazingSmall, true ); }
  void BM_LargeGrazingCold( benchmark::State &state ) { run( state, scene().large, scene().grazingLarge, true ); }
  void BM_SmallGrazingWarm( benchmark::State &state ) { run( state, scene().small, scene().grazingSmall, false ); }
  void BM_LargeGrazingWarm( benchmark::State &state ) { run( state, scene().large, scene().grazingLarge, false ); }
  //! The tile cache made large enough for the grazing fan's tiles (1024 tiles, 270 MB)
  void BM_LargeGrazingWarm1024( benchmark::State &state ) { run( state, scene().large, scene().grazingLarge, false, 1024 ); }
  //! Every tile the fan crosses read once (a cache larger than the fan's tiles): how many they are
  void BM_LargeGrazingCold4096( benchmark::State &state ) { run( state, scene().large, scene().grazingLarge, true, 4096 ); }
}

BENCHMARK( BM_SmallNadirCold )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_LargeNadirCold )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_SmallGrazingCold )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_LargeGrazingCold )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_SmallGrazingWarm )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_LargeGrazingWarm )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_LargeGrazingWarm1024 )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_LargeGrazingCold4096 )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    std::printf( "\nRays per second on the large DEM, against the 2000 x 2000 part of it in this run:\n" );
    for ( const char *kind : { "NadirCold", "GrazingCold", "GrazingWarm", "GrazingWarm1024" } )
    {
      const auto exact = [&rates]( const std::string &name ) { return rates.count( name ) ? rates.at( name ) : 0.0; };
      const std::string k( kind );
      const double large = exact( "BM_Large" + k ), small = exact( "BM_Small" + ( k == "GrazingWarm1024" ? std::string( "GrazingWarm" ) : k ) );
      if ( large > 0 && small > 0 )
        std::printf( "  %-12s %10.0f rays/s (%.2f us per ray), x%.2f of the small DEM's %.0f\n", kind, large, 1e6 / large, large / small, small );
    }
  } );
}
