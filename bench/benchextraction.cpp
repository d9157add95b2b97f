// Road-network extraction (core/extraction) on a simulated aerial pair:
// the coincident procedure (starting points, LEM, REM, verification in the
// partner, alternating rounds, final compilation) on both images.
// Target: a pair of 8000 x 8000 in <= 60 s on the 2 cores, <= 2 GB.
//
// The size is GEOSTATION_BENCH_EXTRACTION_SIZE (default 8000; CI runs 1024).
// Baselines in the same run: one Sobel gradient over both images (reading
// every pixel once), and decoding both image files into the matching
// images (what the Processing algorithm does first). Pixels per second are
// printed per stage, so the slowest stage shows, and the peak resident
// memory from the end of the simulation to the end of the extraction.
// The whole procedure (terrain height, extraction, 3-D lines) is also run
// from the files, read a window at a time and decoded whole, with the
// memory each adds.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

#include <gdal.h>
#include <ogr_api.h>
#include <opencv2/imgproc.hpp>

#include "benchutils.h"
#include "extraction/greytiles.h"
#include "extraction/pairmatchwindows.h"
#include "extraction/roadnetworkextractor.h"
#include "revision/maprevision.h"
#include "io/block.h"
#include "io/rasterfile.h"
#include "matching/matchimage.h"
#include "simulation/surveysimulator.h"

using namespace geostation;

namespace
{
  int pairSize()
  {
    const char *size = std::getenv( "GEOSTATION_BENCH_EXTRACTION_SIZE" );
    return size ? std::max( 256, std::atoi( size ) ) : 8000;
  }

  struct Pair
  {
    std::filesystem::path dir;
    Block block;
    cv::Mat left, right;
    CoincidentExtractionSummary last;

    Pair()
    {
      dir = std::filesystem::temp_directory_path() / ( "geostation-bench-extraction-" + std::to_string( ::getpid() ) );
      SimulationOptions o;
      o.preset = SurveyPreset::AerialStereo;
      o.outputDir = dir;
      o.stations = 2;
      o.imageWidth = o.imageHeight = pairSize();
      o.groundPixelSizeM = 0.5;
      o.supersampling = 1;
      o.seed = 3;
      o.degradation.noiseSigma = 4.0;
      std::printf( "simulating an aerial pair of %d x %d ...\n", pairSize(), pairSize() );
      simulateSurvey( o );
      block = Block::load( dir / "block.geostation.json" );
      left = MatchImage( readRaster( block.imageFilePath( block.images.at( 0 ) ).string() ).pixels ).grey();
      right = MatchImage( readRaster( block.imageFilePath( block.images.at( 1 ) ).string() ).pixels ).grey();
      // the simulation's peak is not the extraction's: start the high-water mark afresh (Linux: clear_refs 5)
      std::ofstream( "/proc/self/clear_refs" ) << "5";
    }
    ~Pair()
    {
      std::error_code ec;
      std::filesystem::remove_all( dir, ec );
    }
  };

  Pair &pair()
  {
    static Pair p;
    return p;
  }

  CoincidentExtractionOptions options()
  {
    CoincidentExtractionOptions o;
    o.extraction.object.polarity = -1;
    o.extraction.object.minContrast = 25.0;
    o.extraction.object.minWidthPx = 6.0;
    o.extraction.object.maxWidthPx = 20.0;
    return o;
  }

  long extractionPeakKb = -1;
  long revisionAddedKb = -1; //!< the revision's peak over what the process held before it (the images held)

  long peakResidentKb() { return benchutils::statusKb( "VmHWM:" ); }
  long residentKb() { return benchutils::statusKb( "VmRSS:" ); }

  void BM_ExtractPair( benchmark::State &state )
  {
    Pair &p = pair();
    const OrientedPairMapping mapping( p.block.orientedImage( p.block.images.at( 0 ) ), p.block.orientedImage( p.block.images.at( 1 ) ), 200.0 );
    for ( auto _ : state )
      p.last = extractCoincident( p.left, p.right, mapping, options() );
    extractionPeakKb = peakResidentKb();
    state.SetItemsProcessed( state.iterations() * 2 * static_cast<int64_t>( p.left.total() ) );
    state.SetLabel( std::to_string( p.last.linesA.size() ) + " lines" );
  }

  RoadNetworkOptions networkOptions()
  {
    RoadNetworkOptions o;
    o.coincident = options();
    return o;
  }

  //! Memory the whole procedure added to what the process held before it (kB), and its 3-D vertices; by how the images were read.
  struct FromFiles
  {
    long addedKb = -1;
    int vertices = 0;
    long windows = 0;
  } windowed, whole, defaultsWindowed;

  /**
   * The whole procedure from the two image files, as geostation:extract_roads
   * runs it: terrain height by matching, extraction, 3-D lines. `inWindows`:
   * read a window at a time (8-bit images); else decoded whole first.
   */
  void runFromFiles( benchmark::State &state, bool inWindows, FromFiles &out, const RoadNetworkOptions &options )
  {
    Pair &p = pair();
    const OrientedImage a = p.block.orientedImage( p.block.images.at( 0 ) ), b = p.block.orientedImage( p.block.images.at( 1 ) );
    const std::string left = p.block.imageFilePath( p.block.images.at( 0 ) ).string(), right = p.block.imageFilePath( p.block.images.at( 1 ) ).string();
    for ( auto _ : state )
    {
      // in a child process of its own, so that its peak memory is its own (not the heap earlier runs left behind)
      int channel[2];
      if ( ::pipe( channel ) != 0 )
        throw std::runtime_error( "no pipe" );
      const pid_t child = ::fork();
      if ( child == 0 )
      {
        ::close( channel[0] );
        const long before = residentKb();
        RoadNetworkSummary s;
        long windows = 0;
        if ( inWindows )
        {
          const auto readerLeft = std::make_shared<const RasterReader>( left ), readerRight = std::make_shared<const RasterReader>( right );
          s = extractRoadNetwork( readerLeft, readerRight, &a, &b, options );
          windows = s.reading.matchingWindows;
        }
        else
          s = extractRoadNetwork( MatchImage( readRaster( left ).pixels ), MatchImage( readRaster( right ).pixels ), &a, &b, options );
        const long result[3] = { peakResidentKb() - before, s.network.vertices - s.network.unmatched, windows };
        const ssize_t written = ::write( channel[1], result, sizeof( result ) );
        ::_exit( written == sizeof( result ) ? 0 : 1 );
      }
      ::close( channel[1] );
      long result[3] = { -1, 0, 0 };
      const ssize_t got = ::read( channel[0], result, sizeof( result ) );
      ::close( channel[0] );
      int status = 0;
      ::waitpid( child, &status, 0 );
      if ( got != sizeof( result ) || !WIFEXITED( status ) || WEXITSTATUS( status ) != 0 )
      {
        state.SkipWithError( "the run in the child process failed" );
        return;
      }
      out.addedKb = result[0];
      out.vertices = static_cast<int>( result[1] );
      out.windows = result[2];
    }
    state.SetItemsProcessed( state.iterations() * 2 * static_cast<int64_t>( p.left.total() ) );
    state.SetLabel( std::to_string( out.vertices ) + " 3-D vertices" );
  }

  void BM_NetworkFromFilesInWindows( benchmark::State &state ) { runFromFiles( state, true, windowed, networkOptions() ); }
  void BM_NetworkFromFilesWhole( benchmark::State &state ) { runFromFiles( state, false, whole, networkOptions() ); }
  //! What extract_roads does when given nothing but the pair: the defaults, the terrain height found by matching.
  void BM_NetworkDefaultsFromFiles( benchmark::State &state ) { runFromFiles( state, true, defaultsWindowed, defaultRoadNetworkOptions() ); }

  /**
   * The extraction's defaults (either polarity, widths from 3 to 30 m, the
   * contrast from the texture, companions removed) against options tuned
   * to the simulator's dark roads, both on the pair held in memory with a
   * mean height given: what the general defaults cost.
   */
  void extractNetwork( benchmark::State &state, const RoadNetworkOptions &options )
  {
    Pair &p = pair();
    const OrientedImage a = p.block.orientedImage( p.block.images.at( 0 ) ), b = p.block.orientedImage( p.block.images.at( 1 ) );
    const MatchImage left( p.left ), right( p.right );
    RoadNetworkOptions o = options;
    o.meanHeightM = 200.0;
    size_t lines = 0;
    for ( auto _ : state )
      lines = extractRoadNetwork( left, right, &a, &b, o ).extraction.linesA.size();
    state.SetItemsProcessed( state.iterations() * 2 * static_cast<int64_t>( p.left.total() ) );
    state.SetLabel( std::to_string( lines ) + " lines" );
  }

  void BM_NetworkTunedOptions( benchmark::State &state ) { extractNetwork( state, networkOptions() ); }
  void BM_NetworkDefaults( benchmark::State &state ) { extractNetwork( state, defaultRoadNetworkOptions() ); }

  /**
   * Map revision with the defaults and without new roads (the pair not
   * extracted), its map the simulation's own road centre lines: checking
   * the mapped roads against extracting them (BM_NetworkDefaults).
   */
  void BM_ReviseMapWithoutNewRoads( benchmark::State &state )
  {
    Pair &p = pair();
    const OrientedImage a = p.block.orientedImage( p.block.images.at( 0 ) ), b = p.block.orientedImage( p.block.images.at( 1 ) );
    std::vector<MapRoad> map;
    GDALAllRegister();
    if ( GDALDatasetH ds = GDALOpenEx( ( p.dir / "truth.gpkg" ).string().c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr ) )
    {
      OGRLayerH layer = GDALDatasetGetLayerByName( ds, "roads" );
      OGRFeatureH f;
      while ( layer && ( f = OGR_L_GetNextFeature( layer ) ) )
      {
        const std::string kind = OGR_F_GetFieldAsString( f, OGR_F_GetFieldIndex( f, "kind" ) );
        if ( OGRGeometryH g = OGR_F_GetGeometryRef( f ); g && kind == "centre" )
        {
          MapRoad road;
          for ( int i = 0; i < OGR_G_GetPointCount( g ); ++i )
            road.vertices.emplace_back( OGR_G_GetX( g, i ), OGR_G_GetY( g, i ), std::nan( "" ) );
          map.push_back( road );
        }
        OGR_F_Destroy( f );
      }
      GDALClose( ds );
    }
    MapRevisionOptions options;
    options.findNewRoads = false;
    options.network.meanHeightM = 200.0;
    const MatchImage left( p.left ), right( p.right );
    double confirmed = 0.0;
    const long before = residentKb();
    std::ofstream( "/proc/self/clear_refs" ) << "5"; // the high-water mark afresh
    for ( auto _ : state )
      confirmed = reviseRoads( left, right, a, b, map, options ).lengthM( RevisionStatus::Confirmed );
    revisionAddedKb = peakResidentKb() - before;
    state.SetItemsProcessed( state.iterations() * 2 * static_cast<int64_t>( p.left.total() ) );
    state.SetLabel( std::to_string( map.size() ) + " map roads, " + std::to_string( static_cast<int>( confirmed ) ) + " m confirmed" );
  }

  void BM_BaselineSobel( benchmark::State &state )
  {
    Pair &p = pair();
    cv::Mat gx;
    for ( auto _ : state )
    {
      cv::Sobel( p.left, gx, CV_16S, 1, 0 );
      cv::Sobel( p.right, gx, CV_16S, 1, 0 );
    }
    state.SetItemsProcessed( state.iterations() * 2 * static_cast<int64_t>( p.left.total() ) );
  }

  void BM_BaselineDecode( benchmark::State &state )
  {
    Pair &p = pair();
    for ( auto _ : state )
      for ( int i = 0; i < 2; ++i )
        benchmark::DoNotOptimize( MatchImage( readRaster( p.block.imageFilePath( p.block.images.at( i ) ).string() ).pixels ) );
    state.SetItemsProcessed( state.iterations() * 2 * static_cast<int64_t>( p.left.total() ) );
  }

}

BENCHMARK( BM_ExtractPair )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_NetworkFromFilesInWindows )->Unit( benchmark::kMillisecond )->Iterations( 1 )->UseRealTime();
BENCHMARK( BM_NetworkFromFilesWhole )->Unit( benchmark::kMillisecond )->Iterations( 1 )->UseRealTime();
BENCHMARK( BM_NetworkTunedOptions )->Unit( benchmark::kMillisecond )->Iterations( 1 )->UseRealTime();
BENCHMARK( BM_NetworkDefaults )->Unit( benchmark::kMillisecond )->Iterations( 1 )->UseRealTime();
BENCHMARK( BM_NetworkDefaultsFromFiles )->Unit( benchmark::kMillisecond )->Iterations( 1 )->UseRealTime();
BENCHMARK( BM_ReviseMapWithoutNewRoads )->Unit( benchmark::kMillisecond )->Iterations( 1 )->UseRealTime();
BENCHMARK( BM_BaselineSobel )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_BaselineDecode )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const double extract = benchutils::rate( rates, "BM_ExtractPair" ), sobel = benchutils::rate( rates, "BM_BaselineSobel" ),
                 decode = benchutils::rate( rates, "BM_BaselineDecode" );
    const int n = pairSize();
    std::printf( "\nA pair of %d x %d: %.1f s for the extraction (target <= 60 s at 8000 x 8000); %.0f Mpx/s, "
                 "x%.0f the time of a Sobel pass, x%.1f the time of decoding the two files\n",
                 n, n, extract > 0 ? 2.0 * n * n / extract : 0.0, extract / 1e6, extract > 0 ? sobel / extract : 0.0, extract > 0 ? decode / extract : 0.0 );
    const CoincidentExtractionSummary &s = pair().last;
    const auto line = []( const char *name, const StageCounts &c, bool image )
    {
      const double amount = image ? static_cast<double>( c.imagePixels ) : c.linePx;
      std::printf( "  %-16s %8.3f s  %12.0f %s px/s\n", name, c.seconds, c.seconds > 0 ? amount / c.seconds : 0.0, image ? "image" : "line " );
    };
    line( "starting points", s.startStage, true );
    line( "LEM", s.lemStage, false );
    line( "REM", s.remStage, false );
    line( "verification", s.verificationStage, false );
    std::printf( "  %-16s %8.3f s\n", "compilation", s.compilationStage.seconds );
    std::printf( "Peak resident memory during the extraction (the two grey images held): %.0f MB (target <= 2048 MB)\n", extractionPeakKb / 1024.0 );
    const double inWindows = benchutils::rate( rates, "BM_NetworkFromFilesInWindows" ), wholeImages = benchutils::rate( rates, "BM_NetworkFromFilesWhole" );
    std::printf( "\nThe whole procedure from the files (terrain height, extraction, 3-D lines):\n"
                 "  read in windows: %.1f s, %.0f MB of memory added (%ld matching windows), %d 3-D vertices\n"
                 "  decoded whole:   %.1f s, %.0f MB of memory added, %d 3-D vertices\n"
                 "  windows: x%.2f the time, x%.2f the memory\n",
                 inWindows > 0 ? 2.0 * n * n / inWindows : 0.0, windowed.addedKb / 1024.0, windowed.windows, windowed.vertices,
                 wholeImages > 0 ? 2.0 * n * n / wholeImages : 0.0, whole.addedKb / 1024.0, whole.vertices,
                 inWindows > 0 ? wholeImages / inWindows : 0.0, whole.addedKb > 0 ? static_cast<double>( windowed.addedKb ) / whole.addedKb : 0.0 );
    const double tuned = benchutils::rate( rates, "BM_NetworkTunedOptions" ), defaults = benchutils::rate( rates, "BM_NetworkDefaults" );
    std::printf( "\nThe defaults (either polarity, 3-30 m, contrast from the texture) against options tuned to these roads: "
                 "%.1f s against %.1f s, x%.2f the time (aim: at most x2)\n",
                 defaults > 0 ? 2.0 * n * n / defaults : 0.0, tuned > 0 ? 2.0 * n * n / tuned : 0.0, defaults > 0 ? tuned / defaults : 0.0 );
    const double defaultsFromFiles = benchutils::rate( rates, "BM_NetworkDefaultsFromFiles" );
    std::printf( "The whole procedure with the defaults from the files (terrain height found, read in windows): %.1f s (target <= 60 s at 8000 x 8000), "
                 "%.0f MB of memory added, %d 3-D vertices\n",
                 defaultsFromFiles > 0 ? 2.0 * n * n / defaultsFromFiles : 0.0, defaultsWindowed.addedKb / 1024.0, defaultsWindowed.vertices );
    const double revise = benchutils::rate( rates, "BM_ReviseMapWithoutNewRoads" );
    std::printf( "Map revision of the pair's own roads without new roads: %.1f s, x%.2f the time of extracting with the defaults (aim: at most x0.5); "
                 "%.1f MB of memory added at its peak (the images held before it)\n",
                 revise > 0 ? 2.0 * n * n / revise : 0.0, revise > 0 ? defaults / revise : 0.0, revisionAddedKb / 1024.0 );
  } );
}
