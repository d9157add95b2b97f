// Adjustment speed: space intersection (target >= 1 M points/s) and space
// resection (target <= 1 ms per image). Baselines measured in the same run:
// cv::triangulatePoints for two-ray intersection, cv::solvePnP (iterative
// Levenberg-Marquardt) for resection.
#include <atomic>
#include <chrono>
#include <thread>
#include <random>

#include <benchmark/benchmark.h>

#include "benchutils.h"
#include <opencv2/calib3d.hpp>

#include "adjustment/bundleadjustment.h"
#include "adjustment/intersection.h"
#include "adjustment/resection.h"
#include "geometry/rotation.h"
#include "bundlescene.h"
#include "pinholecamera.h"

using namespace geostation;

namespace
{
  Camera pinhole() { return centredPinhole( "bench", 1280, 960, 1100.0 ); }

  ExteriorOrientation forward( double x )
  {
    // Looking north, horizontal: omega = 90.
    ExteriorOrientation eo;
    eo.projectionCentre = { 500000.0 + x, 4400000.0, 102.5 };
    eo.omegaDeg = 90.0;
    return eo;
  }

  struct Scene
  {
    OrientedImage left { pinhole(), forward( -1.0 ) };
    OrientedImage right { pinhole(), forward( 1.0 ) };
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> pixelsLeft, pixelsRight;
    Scene()
    {
      std::mt19937 rng( 1 );
      std::uniform_real_distribution<double> x( -4, 4 ), y( 10, 40 ), z( 100, 105 );
      std::normal_distribution<double> noise( 0.0, 0.3 );
      for ( int i = 0; i < 10000; ++i )
      {
        const Eigen::Vector3d p( 500000.0 + x( rng ), 4400000.0 + y( rng ), z( rng ) );
        points.push_back( p );
        pixelsLeft.push_back( left.projectGroundToPixel( p ).pixelInImage + Eigen::Vector2d( noise( rng ), noise( rng ) ) );
        pixelsRight.push_back( right.projectGroundToPixel( p ).pixelInImage + Eigen::Vector2d( noise( rng ), noise( rng ) ) );
      }
    }
  };

  const Scene &scene()
  {
    static const Scene s;
    return s;
  }

  cv::Matx34d projectionMatrix( const OrientedImage &image )
  {
    // OpenCV frame (y down, z forward), pixel centres at integers.
    const Eigen::Matrix3d cvFromWorld = Eigen::DiagonalMatrix<double, 3>( 1, -1, -1 ) * image.cameraFromWorldRotation();
    const Eigen::Vector3d t = -cvFromWorld * image.exterior().projectionCentre;
    const Camera &c = image.camera();
    Eigen::Matrix<double, 3, 4> Rt;
    Rt << cvFromWorld, t;
    Eigen::Matrix3d K;
    K << c.fx(), 0, c.cx - 0.5, 0, c.fy(), c.cy - 0.5, 0, 0, 1;
    const Eigen::Matrix<double, 3, 4> P = K * Rt;
    cv::Matx34d out;
    for ( int r = 0; r < 3; ++r )
      for ( int k = 0; k < 4; ++k )
        out( r, k ) = P( r, k );
    return out;
  }

  void BM_OpenCvTriangulatePoints( benchmark::State &state )
  {
    const Scene &s = scene();
    const cv::Matx34d P1 = projectionMatrix( s.left ), P2 = projectionMatrix( s.right );
    cv::Mat x1( 2, static_cast<int>( s.points.size() ), CV_64F ), x2( 2, static_cast<int>( s.points.size() ), CV_64F );
    for ( size_t i = 0; i < s.points.size(); ++i )
    {
      x1.at<double>( 0, i ) = s.pixelsLeft[i].x() - 0.5;
      x1.at<double>( 1, i ) = s.pixelsLeft[i].y() - 0.5;
      x2.at<double>( 0, i ) = s.pixelsRight[i].x() - 0.5;
      x2.at<double>( 1, i ) = s.pixelsRight[i].y() - 0.5;
    }
    cv::Mat out;
    for ( auto _ : state )
    {
      cv::triangulatePoints( P1, P2, x1, x2, out );
      benchmark::DoNotOptimize( out.data );
    }
    state.SetItemsProcessed( state.iterations() * s.points.size() );
  }

  void BM_IntersectRays( benchmark::State &state )
  {
    const Scene &s = scene();
    std::vector<RayObservation> obs( 2 );
    for ( auto _ : state )
    {
      double sum = 0.0;
      for ( size_t i = 0; i < s.points.size(); ++i )
      {
        obs[0] = { &s.left, s.pixelsLeft[i], 0.5 };
        obs[1] = { &s.right, s.pixelsRight[i], 0.5 };
        sum += intersectRays( obs ).point.z();
      }
      benchmark::DoNotOptimize( sum );
    }
    state.SetItemsProcessed( state.iterations() * s.points.size() );
  }

  std::vector<ControlPoint> control( int count )
  {
    const Scene &s = scene();
    std::vector<ControlPoint> out;
    for ( int i = 0; i < count; ++i )
      out.push_back( { "P" + std::to_string( i ), s.points[i], Eigen::Vector3d::Zero(), false } );
    return out;
  }

  void BM_OpenCvSolvePnPIterative( benchmark::State &state )
  {
    const Scene &s = scene();
    const int n = static_cast<int>( state.range( 0 ) );
    std::vector<cv::Point3d> objectPoints;
    std::vector<cv::Point2d> imagePoints;
    for ( int i = 0; i < n; ++i )
    {
      objectPoints.emplace_back( s.points[i].x() - 500000.0, s.points[i].y() - 4400000.0, s.points[i].z() - 100.0 );
      imagePoints.emplace_back( s.pixelsLeft[i].x() - 0.5, s.pixelsLeft[i].y() - 0.5 );
    }
    const cv::Matx33d K( 1100, 0, 639.5, 0, 1100, 479.5, 0, 0, 1 );
    for ( auto _ : state )
    {
      cv::Mat rvec, tvec;
      cv::solvePnP( objectPoints, imagePoints, K, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_ITERATIVE );
      benchmark::DoNotOptimize( tvec.data );
    }
    state.SetItemsProcessed( state.iterations() );
  }

  void BM_ResectImage( benchmark::State &state )
  {
    const Scene &s = scene();
    const int n = static_cast<int>( state.range( 0 ) );
    const std::vector<ControlPoint> gcps = control( n );
    std::vector<ImagePoint> measured;
    for ( int i = 0; i < n; ++i )
      measured.push_back( { gcps[i].id, s.pixelsLeft[i], 0.5 } );
    ResectionOptions options;
    options.removeBlunders = false;
    for ( auto _ : state )
    {
      const ResectionSummary r = resectImage( s.left.camera(), gcps, measured, options );
      benchmark::DoNotOptimize( r.sigma0 );
    }
    state.SetItemsProcessed( state.iterations() );
  }

  //! Six images (two stations of three cameras) and 10 000 points seen by all.
  void BM_BundleAdjust6x10000( benchmark::State &state )
  {
    static const BundleScene scene( 10000 );
    BundleOptions options;
    options.computeCovariance = state.range( 0 ) != 0;
    for ( auto _ : state )
    {
      const BundleSummary s = bundleAdjust( scene.cameras, scene.images, scene.control, scene.observations, options );
      if ( !s.ok() )
        state.SkipWithError( s.message.c_str() );
      benchmark::DoNotOptimize( s.sigma0 );
    }
    state.SetItemsProcessed( state.iterations() );
    state.SetLabel( options.computeCovariance ? "with covariance" : "solve only" );
  }

  /**
   * Cancel during the adjustment of 6 x 10 000 points, as Cancel in QGIS
   * does it: another thread raises a flag after range(0) ms, which
   * the options' Progress asks after each iteration. Reports the time from the flag to bundleAdjust()'s
   * return (the worst over the repetitions).
   */
  void BM_BundleAdjustCancel6x10000( benchmark::State &state )
  {
    static const BundleScene scene( 10000 );
    using Clock = std::chrono::steady_clock;
    double worstLatencyS = 0.0;
    for ( auto _ : state )
    {
      std::atomic<bool> cancel { false };
      Clock::time_point cancelledAt;
      BundleOptions options;
      options.progress = Progress( nullptr, [&cancel] { return cancel.load(); } );
      std::thread canceller( [&]
      {
        std::this_thread::sleep_for( std::chrono::milliseconds( state.range( 0 ) ) );
        cancelledAt = Clock::now();
        cancel = true;
      } );
      const BundleSummary s = bundleAdjust( scene.cameras, scene.images, scene.control, scene.observations, options );
      const Clock::time_point returned = Clock::now();
      canceller.join();
      if ( s.status != BundleSummary::Status::Cancelled )
      {
        state.SkipWithError( "the adjustment ended before the cancel" );
        break;
      }
      worstLatencyS = std::max( worstLatencyS, std::chrono::duration<double>( returned - cancelledAt ).count() );
    }
    state.counters["cancel_latency_ms"] = 1e3 * worstLatencyS;
    state.SetLabel( "cancelled after " + std::to_string( state.range( 0 ) ) + " ms" );
  }

} // namespace

BENCHMARK( BM_OpenCvTriangulatePoints )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_IntersectRays )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_OpenCvSolvePnPIterative )->Arg( 10 )->Arg( 30 )->Unit( benchmark::kMicrosecond );
BENCHMARK( BM_ResectImage )->Arg( 10 )->Arg( 30 )->Unit( benchmark::kMicrosecond );
BENCHMARK( BM_BundleAdjust6x10000 )->Arg( 0 )->Arg( 1 )->Unit( benchmark::kMillisecond )->UseRealTime();
BENCHMARK( BM_BundleAdjustCancel6x10000 )->Arg( 100 )->Arg( 400 )->Unit( benchmark::kMillisecond )->UseRealTime()->Iterations( 3 );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const auto ratio = [&rates]( const std::string & ours, const std::string & baseline )
    {
      const double a = benchutils::rate( rates, ours ), b = benchutils::rate( rates, baseline );
      if ( a > 0.0 && b > 0.0 )
        printf( "  %-34s %12.4g /s  x%.2f of %s\n", ours.c_str(), a, a / b, baseline.c_str() );
    };
    printf( "\nRates, and ratios to the OpenCV baselines measured in this run:\n" );
    ratio( "BM_IntersectRays", "BM_OpenCvTriangulatePoints" );
    ratio( "BM_ResectImage/10", "BM_OpenCvSolvePnPIterative/10" );
    ratio( "BM_ResectImage/30", "BM_OpenCvSolvePnPIterative/30" );
    for ( const char *name : { "BM_BundleAdjust6x10000/0", "BM_BundleAdjust6x10000/1" } )
      if ( const double r = benchutils::rate( rates, name ); r > 0.0 )
        printf( "  %s: %.3f s per adjustment (target <= 1 s for the solve): %s\n", name, 1.0 / r, 1.0 / r <= 1.0 ? "met" : "NOT met" );
    printf( "  cancel of the 6 x 10 000 adjustment: see cancel_latency_ms above (target: within 1 s of the request)\n" );
    if ( const double r = benchutils::rate( rates, "BM_IntersectRays" ); r > 0.0 )
      printf( "  intersection target >= 1e6 points/s: %s\n", r >= 1e6 ? "met" : "NOT met" );
    if ( const double r = benchutils::rate( rates, "BM_ResectImage/10" ); r > 0.0 )
      printf( "  resection target <= 1 ms per image (10 points): %.3f ms, %s\n", 1e3 / r, r >= 1e3 ? "met" : "NOT met" );
  } );
}
