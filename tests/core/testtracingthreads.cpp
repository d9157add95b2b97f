// Tracing from several threads at once, as QGIS runs Processing algorithms
// side by side and the Multiview traces in the background while the operator
// works: traces share no hidden state (each line comes out vertex for vertex
// as it does alone), and a cancel from another thread stops a trace after
// the station it is in, keeping what was traced. scripts/sanitize.sh
// --thread 'TracingThreads.*' runs it under ThreadSanitizer.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>
#include <unistd.h>

#include "highwaytracing.h"
#include "simulation/surveysimulator.h"
#include "tracing/roadtracer.h"

using namespace geostation;
using namespace geostation::highwaytracing;

namespace
{
  void expectSameLine( const RoadTraceSummary &a, const RoadTraceSummary &b )
  {
    EXPECT_EQ( a.stop, b.stop );
    ASSERT_EQ( a.vertices.size(), b.vertices.size() );
    for ( size_t i = 0; i < a.vertices.size(); ++i )
    {
      EXPECT_EQ( a.vertices[i].point, b.vertices[i].point ) << "vertex " << i;
      EXPECT_EQ( a.vertices[i].sigmaM, b.vertices[i].sigmaM ) << "vertex " << i;
    }
  }
}

TEST( TracingThreads, ConcurrentTracesEqualSequentialOnesAndCancelFromAnotherThread )
{
  // the demo's small run: 640 x 480 cameras every 5 m, eight stations
  SimulationOptions o;
  o.stations = 8;
  o.seed = 3;
  o.threads = 2;
  const HighwayRun run = simulateRun( o, std::filesystem::temp_directory_path() / ( "geostation-tracing-threads-" + std::to_string( ::getpid() ) ) );
  const TraceSeed centre = seedOn( run, "R1-centre1", "S0002_FL", 8.0, Eigen::Vector2d( 1.2, -0.8 ) );
  const TraceSeed kerb = seedOn( run, "R1-edge-right", "S0002_FL", 8.0, Eigen::Vector2d( -0.7, 1.1 ) );
  const RoadTraceOptions options;
  const RoadTraceSummary centreAlone = traceRoadLine( run.block, centre, options, fileGreyImageSource( run.block ) );
  const RoadTraceSummary kerbAlone = traceRoadLine( run.block, kerb, options, fileGreyImageSource( run.block ) );
  ASSERT_GE( centreAlone.stations.size(), 4u ) << centreAlone.message;
  ASSERT_GE( kerbAlone.stations.size(), 4u ) << kerbAlone.message;

  // the two lines, and the centre line a second time, at once
  RoadTraceSummary concurrent[3];
  {
    std::thread threads[3] = {
      std::thread( [&] { concurrent[0] = traceRoadLine( run.block, centre, options, fileGreyImageSource( run.block ) ); } ),
      std::thread( [&] { concurrent[1] = traceRoadLine( run.block, kerb, options, fileGreyImageSource( run.block ) ); } ),
      std::thread( [&] { concurrent[2] = traceRoadLine( run.block, centre, options, fileGreyImageSource( run.block ) ); } ),
    };
    for ( std::thread &t : threads )
      t.join();
  }
  expectSameLine( concurrent[0], centreAlone );
  expectSameLine( concurrent[1], kerbAlone );
  expectSameLine( concurrent[2], centreAlone );

  // cancelled from this thread once the trace has reported two stations, as Esc does in the Multiview
  std::atomic<bool> cancel { false };
  std::atomic<int> reported { 0 };
  RoadTraceOptions cancellable = options;
  cancellable.progress = Progress( nullptr, [&] { return cancel.load(); } );
  cancellable.stationTraced = [&]( const TracedStation &, const std::vector<Eigen::Vector2d> &, const std::vector<Eigen::Vector2d> &, const std::vector<TracedVertex> & )
  {
    ++reported;
  };
  RoadTraceSummary cancelled;
  std::atomic<bool> finished { false };
  std::thread worker( [&]
  {
    cancelled = traceRoadLine( run.block, kerb, cancellable, fileGreyImageSource( run.block ) );
    finished = true;
  } );
  while ( reported.load() < 2 && !finished.load() )
    std::this_thread::yield();
  const auto cancelledAt = std::chrono::steady_clock::now();
  cancel = true;
  worker.join();
  // it stops at the end of the station it is in: within a second of the cancel (the optimised build; a sanitizer's is slower)
  const double waited = std::chrono::duration<double>( std::chrono::steady_clock::now() - cancelledAt ).count();
  EXPECT_EQ( cancelled.stop, TraceStop::Cancelled ) << cancelled.message;
  EXPECT_GE( cancelled.stations.size(), 2u );
  EXPECT_LT( cancelled.stations.size(), kerbAlone.stations.size() );
  // what was traced before the cancel is kept: the line alone's first vertices
  ASSERT_GE( cancelled.vertices.size(), 2u );
  ASSERT_LE( cancelled.vertices.size(), kerbAlone.vertices.size() );
  EXPECT_EQ( cancelled.vertices.front().point, kerbAlone.vertices.front().point );
  std::printf( "centre line %zu vertices, kerb %zu; cancelled after %zu stations with %zu vertices, %.3f s after the cancel\n", centreAlone.vertices.size(),
               kerbAlone.vertices.size(), cancelled.stations.size(), cancelled.vertices.size(), waited );
#if !defined( __SANITIZE_ADDRESS__ ) && !defined( __SANITIZE_THREAD__ )
  EXPECT_LT( waited, 1.0 );
#endif
  std::error_code ec;
  std::filesystem::remove_all( run.dir, ec );
}
