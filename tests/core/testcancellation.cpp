/***************************************************************************
  testcancellation.cpp - long operations stop within a second of a cancel
  -------------------------------------------------------------------------
  Every long operation of core takes one Progress (progress/progress.h)
  and asks it, between steps, whether to stop. The cancel here is asked
  right after a check that let the operation go on - the worst moment:
  the operation runs on to its next check - and the time from there to
  its return is what a user waits after pressing Cancel. The aim: under
  a second, on scenes big enough that the whole operation takes longer.
  (Tracing's is measured in testtracingthreads.cpp, on its run. Timings
  of the optimised build: not run under the sanitizers.)
 ***************************************************************************/
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "adjustment/bundleadjustment.h"
#include "extraction/roadnetworkextractor.h"
#include "identification/controlidentification.h"
#include "matching/matchimage.h"
#include "paintedroads.h"
#include "bundlescene.h"
#include "pinholecamera.h"
#include "progress/progress.h"

using namespace geostation;

namespace
{
  using Clock = std::chrono::steady_clock;

  /**
   * A stop asked right after the `goOn`-th check the operation makes (that
   * check still answered "go on"), and when.
   */
  class CancelAfterChecks
  {
    public:
      explicit CancelAfterChecks( int goOn ) : mGoOn( goOn ) {}

      Progress progress()
      {
        return Progress( nullptr, [this] {
          if ( mAsked )
            return true;
          if ( ++mChecks >= mGoOn )
          {
            mAsked = true;
            mAskedAt = Clock::now();
          }
          return false;
        } );
      }

      bool asked() const { return mAsked; }
      double secondsSinceAsked() const { return std::chrono::duration<double>( Clock::now() - mAskedAt ).count(); }

    private:
      int mGoOn, mChecks = 0;
      bool mAsked = false;
      Clock::time_point mAskedAt;
  };

  double secondsOf( const std::function<void()> &f )
  {
    const Clock::time_point start = Clock::now();
    f();
    return std::chrono::duration<double>( Clock::now() - start ).count();
  }
} // namespace

TEST( CancelWithinASecond, BundleAdjustment )
{
  // six images in two strips, 8 000 points seen in all of them, the starts a little off (bundlescene.h)
  const BundleScene scene( 8000 );
  BundleOptions options;
  BundleSummary whole;
  const double wholeSeconds = secondsOf( [&] { whole = bundleAdjust( scene.cameras, scene.images, scene.control, scene.observations, options ); } );
  ASSERT_TRUE( whole.ok() ) << whole.message;

  CancelAfterChecks cancel( 2 ); // after the first iteration
  options.progress = cancel.progress();
  const BundleSummary stopped = bundleAdjust( scene.cameras, scene.images, scene.control, scene.observations, options );
  ASSERT_TRUE( cancel.asked() );
  const double waited = cancel.secondsSinceAsked();
  std::printf( "bundle adjustment of 6 x 8000: %.2f s whole (%d iterations), stopped %.3f s after the cancel\n", wholeSeconds, whole.iterations, waited );
  EXPECT_EQ( stopped.status, BundleSummary::Status::Cancelled ) << stopped.message;
  EXPECT_LT( waited, 1.0 );
}

TEST( CancelWithinASecond, RoadExtraction )
{
  // the painted aerial pair (1200 x 900 px: two sub-images), extracted with the defaults
  const paintedroads::PaintedRoadPair pair = paintedroads::paintedRoadPair( paintedroads::scenes()[1] );
  const OrientedImage a( pair.camera, pair.exterior[0] ), b( pair.camera, pair.exterior[1] );
  const MatchImage imageA( pair.grey[0] ), imageB( pair.grey[1] );
  RoadNetworkSummary whole;
  const double wholeSeconds = secondsOf( [&] { whole = extractRoadNetwork( imageA, imageB, &a, &b, defaultRoadNetworkOptions() ); } );
  ASSERT_FALSE( whole.extraction.cancelled );

  for ( const int goOn : { 2, 3 } ) // before the first sub-image; before the second, whose round's verification follows
  {
    CancelAfterChecks cancel( goOn );
    const RoadNetworkSummary stopped = extractRoadNetwork( imageA, imageB, &a, &b, defaultRoadNetworkOptions(), cancel.progress() );
    ASSERT_TRUE( cancel.asked() );
    const double waited = cancel.secondsSinceAsked();
    std::printf( "road extraction of 1200 x 900 px: %.2f s whole, stopped %.3f s after a cancel at check %d\n", wholeSeconds, waited, goOn );
    EXPECT_TRUE( stopped.extraction.cancelled );
    EXPECT_TRUE( stopped.network.lines.empty() );
    EXPECT_LT( waited, 1.0 );
  }
}

TEST( CancelWithinASecond, ControlIdentification )
{
  // 60 control points and 250 candidates, none of them a control point: the search runs through every candidate
  std::mt19937 random( 7 );
  std::uniform_real_distribution<double> u( -150, 150 ), col( 0, 1600 ), row( 0, 1200 );
  std::vector<ControlPoint> control;
  for ( int k = 0; k < 60; ++k )
    control.push_back( { "GCP" + std::to_string( k ), Eigen::Vector3d( 500000 + u( random ), 6000000 + u( random ), 80.0 ), Eigen::Vector3d::Zero(), false } );
  std::vector<Eigen::Vector2d> candidates;
  for ( int k = 0; k < 250; ++k )
    candidates.emplace_back( col( random ), row( random ) );
  const Camera camera = centredPinhole( "photo", 1600, 1200, 1800.0 );
  ControlIdentificationOptions options;
  ControlIdentificationSummary whole;
  const double wholeSeconds = secondsOf( [&] { whole = identifyControl( camera, control, candidates, options ); } );
  ASSERT_NE( whole.status, ControlIdentificationSummary::Status::Cancelled );

  CancelAfterChecks cancel( 10 );
  options.progress = cancel.progress();
  const ControlIdentificationSummary stopped = identifyControl( camera, control, candidates, options );
  ASSERT_TRUE( cancel.asked() );
  const double waited = cancel.secondsSinceAsked();
  std::printf( "identification among 250 candidates: %.2f s whole (%ld poses), stopped %.3f s after the cancel\n", wholeSeconds, whole.poses, waited );
  EXPECT_EQ( stopped.status, ControlIdentificationSummary::Status::Cancelled ) << stopped.message;
  EXPECT_LT( waited, 1.0 );
}

TEST( Progress, APartReportsIntoItsSpanAndAStopHolds )
{
  std::vector<double> told;
  bool stop = false;
  const Progress whole( [&]( double f, const std::string & ) { told.push_back( f ); }, [&] { return stop; } );
  const Progress second = whole.part( 0.5, 1.0 ), quarter = second.part( 0.5, 1.0 );
  EXPECT_TRUE( quarter.report( 0.5 ) );
  EXPECT_TRUE( second.report( 2.0 ) ); // clamped
  ASSERT_EQ( told.size(), 2u );
  EXPECT_DOUBLE_EQ( told[0], 0.875 );
  EXPECT_DOUBLE_EQ( told[1], 1.0 );
  stop = true;
  EXPECT_FALSE( quarter.report( 0.9 ) );
  stop = false;
  EXPECT_TRUE( whole.stopRequested() ) << "once asked, always";
  EXPECT_FALSE( Progress().stopRequested() );
  EXPECT_TRUE( Progress().report( 0.3, "nowhere" ) );
  EXPECT_THROW( whole.part( 0.6, 0.4 ), std::invalid_argument );
}
