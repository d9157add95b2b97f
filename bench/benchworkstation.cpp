// The Multiview's click: from a pixel clicked in one view to the epipolar
// curves and proposed conjugate points in the 5 other views of a 6-camera
// van at 1920 x 1080 (simulated highway station). Target: <= 100 ms per
// click. Baseline in the same run: the same curves, then each other view
// searched by cv::matchTemplate (normalised cross-correlation) over the
// bounding box of its curve. Also: preparing a station's six images for
// matching (the work the Multiview does in the background while the
// operator looks at a station).
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include <opencv2/imgproc.hpp>

#include "benchutils.h"
#include "io/block.h"
#include "io/rasterfile.h"
#include "simulation/surveysimulator.h"
#include "simulationtruth.h"
#include "workstation/matchimagecache.h"
#include "workstation/pointmeasurer.h"

using namespace geostation;

namespace
{
  struct Station
  {
    std::filesystem::path dir;
    Block block;
    std::vector<std::string> paths;
    std::vector<OrientedImage> oriented;
    std::vector<std::shared_ptr<const MatchImage>> pixels;
    std::vector<MeasurementView> views;
    std::vector<Eigen::Vector2d> clicks;

    Station()
    {
      dir = std::filesystem::temp_directory_path() / ( "geostation-bench-ws-" + std::to_string( ::getpid() ) );
      SimulationOptions options;
      options.preset = SurveyPreset::Highway;
      options.seed = 3;
      options.outputDir = dir;
      options.stations = 2;
      options.cameras = 6;
      options.imageWidth = 1920;
      options.imageHeight = 1080;
      options.supersampling = 1;
      options.poseNoiseScale = 0.0;
      options.degradation.noiseSigma = 1.0;
      simulateSurvey( options );
      block = Block::load( dir / "block.geostation.json" );
      const TruthTable truth = readTruth( dir / "truth.gpkg" );
      MatchImageCache cache;
      for ( const BlockImage &image : block.images )
      {
        if ( image.stationId != block.images.front().stationId )
          continue;
        paths.push_back( block.imageFilePath( image ).string() );
        oriented.push_back( block.orientedImage( image ) );
        pixels.push_back( cache.get( paths.back() ).image );
      }
      for ( size_t i = 0; i < oriented.size(); ++i )
        views.push_back( MeasurementView { block.images[i].id, &oriented[i], pixels[i].get() } );
      // what an operator clicks: the objects and road points of the first view
      for ( const auto &[key, pixel] : truth.imageTruth )
        if ( key.second == views[0].imageId && clicks.size() < 40 )
          clicks.push_back( pixel );
    }
    ~Station() { std::filesystem::remove_all( dir ); }
  };

  Station &station()
  {
    static Station s;
    return s;
  }

  void BM_ClickToProposals( benchmark::State &state )
  {
    Station &s = station();
    size_t matched = 0;
    for ( auto _ : state )
      for ( const Eigen::Vector2d &click : s.clicks )
        for ( const ConjugateProposal &p : proposeConjugates( s.views, 0, click ) )
          matched += p.matched();
    benchmark::DoNotOptimize( matched );
    state.SetItemsProcessed( state.iterations() * s.clicks.size() );
    state.SetLabel( std::to_string( s.views.size() - 1 ) + " other views" );
  }

  void BM_BaselineCurvesAndMatchTemplate( benchmark::State &state )
  {
    Station &s = station();
    const ProposalOptions options;
    double sum = 0;
    cv::Mat result;
    for ( auto _ : state )
      for ( const Eigen::Vector2d &click : s.clicks )
      {
        const cv::Mat &reference = s.pixels[0]->grey();
        const int cx = static_cast<int>( click.x() ), cy = static_cast<int>( click.y() );
        if ( cx < 7 || cy < 7 || cx + 8 > reference.cols || cy + 8 > reference.rows )
          continue;
        const cv::Mat window = reference( cv::Rect( cx - 7, cy - 7, 15, 15 ) );
        for ( size_t v = 1; v < s.views.size(); ++v )
        {
          const EpipolarCurve curve = epipolarCurve( s.oriented[0], click, s.oriented[v], options.epipolar );
          cv::Rect box;
          bool any = false;
          for ( const auto &piece : curve.pieces )
            for ( const EpipolarVertex &vertex : piece )
              if ( vertex.inFrame )
              {
                const cv::Rect at( static_cast<int>( vertex.pixelInImage.x() ) - 8, static_cast<int>( vertex.pixelInImage.y() ) - 8, 17, 17 );
                box = any ? ( box | at ) : at;
                any = true;
              }
          const cv::Mat &search = s.pixels[v]->grey();
          box &= cv::Rect( 0, 0, search.cols, search.rows );
          if ( !any || box.width < 15 || box.height < 15 )
            continue;
          cv::matchTemplate( search( box ), window, result, cv::TM_CCOEFF_NORMED );
          double best;
          cv::minMaxLoc( result, nullptr, &best );
          sum += best;
        }
      }
    benchmark::DoNotOptimize( sum );
    state.SetItemsProcessed( state.iterations() * s.clicks.size() );
  }

  void BM_PrepareStationImages( benchmark::State &state )
  {
    Station &s = station();
    for ( auto _ : state )
    {
      MatchImageCache cache;
      for ( const std::string &path : s.paths )
        benchmark::DoNotOptimize( cache.get( path ).image );
    }
    state.SetItemsProcessed( state.iterations() * s.paths.size() );
  }
}

BENCHMARK( BM_ClickToProposals )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_BaselineCurvesAndMatchTemplate )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_PrepareStationImages )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const double ours = benchutils::rate( rates, "BM_ClickToProposals" ), baseline = benchutils::rate( rates, "BM_BaselineCurvesAndMatchTemplate" );
    const double prepare = benchutils::rate( rates, "BM_PrepareStationImages" );
    printf( "\nOne core, 6 cameras at 1920 x 1080:\n" );
    if ( ours > 0 )
      printf( "  click to curves and proposals in 5 other views: %.2f ms (target <= 100: %s)", 1e3 / ours, 1e3 / ours <= 100.0 ? "met" : "NOT met" );
    if ( ours > 0 && baseline > 0 )
      printf( "; x%.1f of curves + cv::matchTemplate over each curve's bounding box", ours / baseline );
    printf( "\n" );
    if ( prepare > 0 )
      printf( "  preparing one image for matching (read, grey, B-spline): %.1f ms\n", 1e3 / prepare );
  } );
}
