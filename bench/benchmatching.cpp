// Area matching speed, one core. Targets: NCC along a 128-px epipolar band
// with a 15 x 15 window <= 5 us per point and >= 10 x faster than calling
// cv::matchTemplate on the same windows; dense NCC >= 2 x OpenCV's positions
// per second; least-squares matching <= 50 us.
#include <cstdio>
#include <random>

#include <opencv2/imgproc.hpp>

#include "benchutils.h"
#include "matching/areamatcher.h"

using namespace geostation;

namespace
{
  struct Images
  {
    cv::Mat left, right;
    std::unique_ptr<MatchImage> leftMatch, rightMatch;
    std::vector<Eigen::Vector2d> points;
    Images()
    {
      cv::Mat noise( 1024, 1024, CV_32F );
      cv::RNG rng( 7 );
      rng.fill( noise, cv::RNG::NORMAL, 0.0, 50.0 );
      cv::GaussianBlur( noise, noise, cv::Size( 0, 0 ), 1.2 );
      noise.convertTo( left, CV_8U, 1.0, 128.0 );
      const cv::Mat shift = ( cv::Mat_<double>( 2, 3 ) << 1, 0, 37.4, 0, 1, 0.3 );
      cv::warpAffine( left, right, shift, left.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT );
      leftMatch = std::make_unique<MatchImage>( left );
      rightMatch = std::make_unique<MatchImage>( right );
      std::mt19937 random( 3 );
      std::uniform_real_distribution<double> u( 100, 800 );
      for ( int k = 0; k < 200; ++k )
        points.emplace_back( u( random ), u( random ) );
    }
  };
  const Images &images()
  {
    static Images i;
    return i;
  }

  //! 128 candidate centres along a horizontal band through the true match.
  std::vector<cv::Point> band( const Eigen::Vector2d &p )
  {
    std::vector<cv::Point> out;
    for ( int k = 0; k < 128; ++k )
      out.emplace_back( static_cast<int>( p.x() ) + 37 - 64 + k, static_cast<int>( p.y() ) );
    return out;
  }

  void BM_NccBand15x15( benchmark::State &state )
  {
    const Images &im = images();
    double sum = 0;
    for ( auto _ : state )
      for ( const Eigen::Vector2d &p : im.points )
      {
        const CorrelationTemplate t( *im.leftMatch, static_cast<int>( p.x() ), static_cast<int>( p.y() ), 15, 15, SimilarityMeasure::NCC );
        double best = -2;
        for ( const cv::Point &c : band( p ) )
          best = std::max( best, t.score( *im.rightMatch, c.x, c.y ).value_or( -2.0 ) );
        sum += best;
      }
    benchmark::DoNotOptimize( sum );
    state.SetItemsProcessed( state.iterations() * im.points.size() );
  }

  void BM_MatchTemplateBand15x15( benchmark::State &state )
  {
    const Images &im = images();
    double sum = 0;
    cv::Mat result;
    for ( auto _ : state )
      for ( const Eigen::Vector2d &p : im.points )
      {
        const cv::Mat target = im.left( cv::Rect( static_cast<int>( p.x() ) - 7, static_cast<int>( p.y() ) - 7, 15, 15 ) );
        double best = -2;
        for ( const cv::Point &c : band( p ) )
        {
          cv::matchTemplate( im.right( cv::Rect( c.x - 7, c.y - 7, 15, 15 ) ), target, result, cv::TM_CCOEFF_NORMED );
          best = std::max( best, static_cast<double>( result.at<float>( 0, 0 ) ) );
        }
        sum += best;
      }
    benchmark::DoNotOptimize( sum );
    state.SetItemsProcessed( state.iterations() * im.points.size() );
  }

  //! Dense NCC: every position of a 64 x 64 search area, 15 x 15 window.
  void BM_DenseNcc64( benchmark::State &state )
  {
    const Images &im = images();
    double sum = 0;
    for ( auto _ : state )
      for ( size_t k = 0; k < 20; ++k )
      {
        const Eigen::Vector2d &p = im.points[k];
        const CorrelationTemplate t( *im.leftMatch, static_cast<int>( p.x() ), static_cast<int>( p.y() ), 15, 15, SimilarityMeasure::NCC );
        const cv::Mat scores = t.scoreArea( *im.rightMatch, cv::Rect( static_cast<int>( p.x() ) + 37 - 32, static_cast<int>( p.y() ) - 32, 64, 64 ) );
        sum += scores.at<double>( 32, 32 );
      }
    benchmark::DoNotOptimize( sum );
    state.SetItemsProcessed( state.iterations() * 20 * 64 * 64 );
  }

  void BM_DenseMatchTemplate64( benchmark::State &state )
  {
    const Images &im = images();
    double sum = 0;
    cv::Mat result;
    for ( auto _ : state )
      for ( size_t k = 0; k < 20; ++k )
      {
        const Eigen::Vector2d &p = im.points[k];
        const cv::Mat target = im.left( cv::Rect( static_cast<int>( p.x() ) - 7, static_cast<int>( p.y() ) - 7, 15, 15 ) );
        const cv::Mat area = im.right( cv::Rect( static_cast<int>( p.x() ) + 37 - 32 - 7, static_cast<int>( p.y() ) - 32 - 7, 64 + 14, 64 + 14 ) );
        cv::matchTemplate( area, target, result, cv::TM_CCOEFF_NORMED );
        sum += result.at<float>( 32, 32 );
      }
    benchmark::DoNotOptimize( sum );
    state.SetItemsProcessed( state.iterations() * 20 * 64 * 64 );
  }

  void BM_Lsm9x9( benchmark::State &state )
  {
    const Images &im = images();
    int converged = 0;
    for ( auto _ : state )
      for ( const Eigen::Vector2d &p : im.points )
        converged += leastSquaresMatch( *im.leftMatch, p, *im.rightMatch, p + Eigen::Vector2d( 37.4 + 0.6, 0.3 - 0.5 ) ).converged;
    benchmark::DoNotOptimize( converged );
    state.SetItemsProcessed( state.iterations() * im.points.size() );
  }
}

BENCHMARK( BM_MatchTemplateBand15x15 )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_NccBand15x15 )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_DenseMatchTemplate64 )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_DenseNcc64 )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_Lsm9x9 )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const double ours = benchutils::rate( rates, "BM_NccBand15x15" ), cv = benchutils::rate( rates, "BM_MatchTemplateBand15x15" ), lsm = benchutils::rate( rates, "BM_Lsm9x9" );
    printf( "\nPer point, one core:\n" );
    if ( ours > 0 && cv > 0 )
      printf( "  NCC along a 128-px band, 15 x 15: %.2f us (target <= 5: %s); x%.1f of cv::matchTemplate on the same windows (target x10: %s)\n",
              1e6 / ours, 1e6 / ours <= 5.0 ? "met" : "NOT met", ours / cv, ours / cv >= 10.0 ? "met" : "NOT met" );
    const double dense = benchutils::rate( rates, "BM_DenseNcc64" ), denseCv = benchutils::rate( rates, "BM_DenseMatchTemplate64" );
    if ( dense > 0 && denseCv > 0 )
      printf( "  dense NCC, 64 x 64 positions, 15 x 15: %.1f M positions/s, x%.2f of cv::matchTemplate on the same area (target x2: %s)\n",
              dense / 1e6, dense / denseCv, dense / denseCv >= 2.0 ? "met" : "NOT met" );
    if ( lsm > 0 )
      printf( "  least-squares matching 9 x 9: %.1f us (target <= 50: %s)\n", 1e6 / lsm, 1e6 / lsm <= 50.0 ? "met" : "NOT met" );
  } );
}
