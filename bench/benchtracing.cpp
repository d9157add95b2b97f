// Road tracing (core/tracing) on one core: one line followed from one seed
// through a simulated highway run of 2 cameras at 1920 x 1080.
// Target: >= 20 stations per second headless.
//
// Baseline in the same run: the same line measured vertex by vertex through
// the Multiview's existing path - for every vertex tracing kept, the click
// in the reference image goes through proposeConjugates() (epipolar curve,
// correlation, least squares in the partner) and intersectVertex(). The
// ratio says what tracing saves over clicking the line point by point, even
// before counting the operator's clicks.
//
// Two image sources for tracing: the block's files read through GDAL as the
// Processing algorithm does (decoding included), and the same grey images
// already in memory (the cost of tracing alone).
#include <cstdio>
#include <filesystem>
#include <map>
#include <unistd.h>

#include <opencv2/core.hpp>

#include "benchutils.h"
#include "io/block.h"
#include "linescoring.h"
#include "simulation/surveysimulator.h"
#include "tracing/roadtracer.h"
#include "workstation/matchimagecache.h"
#include "workstation/pointmeasurer.h"

using namespace geostation;

namespace
{
  constexpr int kStations = 12;

  struct Run
  {
    std::filesystem::path dir;
    Block block, truth;
    TraceSeed seed;
    std::map<std::string, GreyImage> grey; //!< image id -> pixels, for the in-memory source
    RoadTraceSummary traced;                                    //!< what the baseline measures again

    Run()
    {
      dir = std::filesystem::temp_directory_path() / ( "geostation-bench-tracing-" + std::to_string( ::getpid() ) );
      SimulationOptions o;
      o.preset = SurveyPreset::Highway;
      o.outputDir = dir;
      o.stations = kStations;
      o.stationSpacingM = 10.0;
      o.cameras = 2;
      o.imageWidth = 1920;
      o.imageHeight = 1080;
      o.supersampling = 1;
      o.seed = 7;
      o.degradation.noiseSigma = 2.0;
      o.degradation.jpegQuality = 85;
      o.poseNoiseScale = 0.2;
      simulateSurvey( o );
      block = Block::load( dir / "block.geostation.json" );
      truth = Block::load( dir / "truth.geostation.json" );
      seed = seedOnCentreLine( readTruthRoadLines( dir / "truth.gpkg" ) );
      const GreyImageSource files = fileGreyImageSource( block, 2 * kStations + 2 );
      for ( const BlockImage &image : block.images )
        grey[image.id] = files( image );
      traced = traceRoadLine( block, seed, RoadTraceOptions(), memorySource() );
      std::printf( "Seed on the centre line in %s at (%.0f, %.0f): %zu stations, %zu vertices, %.0f m traced; %s\n", seed.imageId.c_str(), seed.pixelInImage.x(),
                   seed.pixelInImage.y(), traced.stations.size(), traced.vertices.size(), traced.lengthM, traced.message.c_str() );
    }
    ~Run() { std::filesystem::remove_all( dir ); }

    //! The solid centre line, about 8 m ahead of the first station's first camera, projected by the true orientation.
    TraceSeed seedOnCentreLine( const std::vector<TruthRoadLine> &roads ) const
    {
      const BlockImage &first = truth.images.front();
      const OrientedImage image = truth.orientedImage( first );
      const OrientedImage partner = truth.orientedImage( truth.images[1] );
      const Eigen::Vector3d c = image.exterior().projectionCentre;
      const auto wellInside = []( const GroundProjection &g, const OrientedImage &in )
      {
        const Eigen::Vector2d size( in.camera().width, in.camera().height );
        return g.ok() && g.inFrame && ( g.pixelInImage.array() > 100.0 ).all() && ( g.pixelInImage.array() < size.array() - 100.0 ).all();
      };
      for ( const TruthRoadLine &line : roads )
        if ( line.id.rfind( "R1-centre1-", 0 ) == 0 )
          for ( size_t i = 0; i + 1 < line.vertices.size(); ++i )
            for ( int k = 0; k < 20; ++k )
            {
              const Eigen::Vector3d p = line.vertices[i] + k / 20.0 * ( line.vertices[i + 1] - line.vertices[i] );
              const GroundProjection g = image.projectGroundToPixel( p );
              if ( ( p - c ).head<2>().norm() >= 8.0 && wellInside( g, image ) && wellInside( partner.projectGroundToPixel( p ), partner ) )
                return TraceSeed { "centre", first.id, g.pixelInImage, std::nullopt };
            }
      throw std::runtime_error( "the centre line is not in view of the first station's two images" );
    }

    GreyImageSource memorySource() const
    {
      return [this]( const BlockImage &image ) { return grey.at( image.id ); };
    }
  };

  Run &run()
  {
    static Run r;
    return r;
  }

  void BM_TraceFromFiles( benchmark::State &state )
  {
    Run &r = run();
    size_t stations = 0;
    for ( auto _ : state )
    {
      const RoadTraceSummary s = traceRoadLine( r.block, r.seed, RoadTraceOptions(), fileGreyImageSource( r.block ) );
      stations += s.stations.size();
    }
    state.SetItemsProcessed( static_cast<int64_t>( stations ) );
    state.SetLabel( std::to_string( r.traced.stations.size() ) + " stations" );
  }

  void BM_TraceInMemory( benchmark::State &state )
  {
    Run &r = run();
    size_t stations = 0;
    for ( auto _ : state )
    {
      const RoadTraceSummary s = traceRoadLine( r.block, r.seed, RoadTraceOptions(), r.memorySource() );
      stations += s.stations.size();
    }
    state.SetItemsProcessed( static_cast<int64_t>( stations ) );
    state.SetLabel( std::to_string( r.traced.vertices.size() ) + " vertices" );
  }

  //! Each station's pair alone (no multi-station vertices): what seeing the line from the stations before costs.
  void BM_TraceInMemoryPairsAlone( benchmark::State &state )
  {
    Run &r = run();
    RoadTraceOptions options;
    options.stationsBehind = 0;
    size_t stations = 0;
    for ( auto _ : state )
    {
      const RoadTraceSummary s = traceRoadLine( r.block, r.seed, options, r.memorySource() );
      stations += s.stations.size();
    }
    state.SetItemsProcessed( static_cast<int64_t>( stations ) );
  }

  /**
   * The same vertices, each clicked in its reference image and measured by
   * proposal + intersection. Argument 0: each station's images read and
   * prepared for matching (as tracing from files reads them); 1: all
   * prepared beforehand, as the Multiview does in the background while the
   * operator looks (compare with tracing from memory).
   */
  void BM_BaselineVertexByVertex( benchmark::State &state )
  {
    Run &r = run();
    std::map<std::string, std::vector<const TracedVertex *>> byStation;
    for ( const TracedVertex &v : r.traced.vertices )
      byStation[v.stationId].push_back( &v );
    std::map<std::string, OrientedImage> oriented;
    for ( const BlockImage &image : r.block.images )
      oriented.emplace( image.id, r.block.orientedImage( image ) );
    const bool prepared = state.range( 0 ) == 1;
    MatchImageCache preparedCache( 2 * kStations + 2 );
    for ( const BlockImage &image : r.block.images )
      preparedCache.get( r.block.imageFilePath( image ).string() );
    size_t measured = 0;
    for ( auto _ : state )
    {
      MatchImageCache fileCache( 2 );
      MatchImageCache &cache = prepared ? preparedCache : fileCache;
      for ( const auto &[stationId, vertices] : byStation )
      {
        const TracedVertex &first = *vertices.front();
        std::vector<MeasurementView> views;
        for ( const std::string &id : { first.imageIds[0], first.imageIds[1] } ) // the station's pair
          views.push_back( MeasurementView { id, &oriented.at( id ), cache.get( r.block.imageFilePath( r.block.image( id ) ).string() ).image.get() } );
        for ( const TracedVertex *v : vertices )
        {
          const std::vector<ConjugateProposal> proposals = proposeConjugates( views, 0, v->pixels[0] );
          if ( !proposals[1].matched() )
            continue;
          const MeasuredVertex m = intersectVertex( { VertexObservation { views[0].imageId, views[0].image, v->pixels[0] },
                                                      VertexObservation { views[1].imageId, views[1].image, proposals[1].pixelInImage } } );
          measured += m.ok();
        }
      }
    }
    benchmark::DoNotOptimize( measured );
    state.SetItemsProcessed( static_cast<int64_t>( state.iterations() * byStation.size() ) );
    state.SetLabel( prepared ? "images prepared" : "images read" );
  }
}

BENCHMARK( BM_TraceFromFiles )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_TraceInMemory )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_TraceInMemoryPairsAlone )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_BaselineVertexByVertex )->Arg( 0 )->Arg( 1 )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  cv::setNumThreads( 1 ); // one core
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const double files = benchutils::rate( rates, "BM_TraceFromFiles" ), memory = benchutils::rate( rates, "BM_TraceInMemory" );
    const double baselineFiles = benchutils::rate( rates, "BM_BaselineVertexByVertex/0" );
    const double baselinePrepared = benchutils::rate( rates, "BM_BaselineVertexByVertex/1" );
    printf( "\nOne core, one line, 2 cameras at 1920 x 1080 (stations per second):\n" );
    if ( files > 0 )
      printf( "  tracing, images read from the block's files: %.1f (target >= 20: %s)\n", files, files >= 20.0 ? "met" : "NOT met" );
    if ( baselineFiles > 0 )
      printf( "  baseline, the same vertices clicked one by one, images read:     %.1f (tracing x%.1f)\n", baselineFiles, files / baselineFiles );
    const double pairsAlone = benchutils::rate( rates, "BM_TraceInMemoryPairsAlone" );
    if ( memory > 0 )
      printf( "  tracing, images already in memory:          %.1f\n", memory );
    if ( pairsAlone > 0 && memory > 0 )
      printf( "  the same, each station's pair alone:        %.1f (multi-station vertices cost x%.2f)\n", pairsAlone, pairsAlone / memory );
    if ( baselinePrepared > 0 )
      printf( "  baseline, the same vertices clicked one by one, images prepared: %.1f (tracing x%.1f)\n", baselinePrepared, memory / baselinePrepared );
    printf( "  (the baseline also needs one click per vertex; tracing one click per line)\n" );
  } );
}
