// A high-rate GNSS/INS trajectory and exposure events at other times: the
// pose at each event interpolated (cubic Hermite positions, slerp attitudes)
// against an analytic vehicle motion through a bend, and the whole import
// against the same import of the exact poses at the event times.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "rigcameras.h"
#include "testfiles.h"
#include "geometry/rotation.h"
#include "geometry/trajectoryinterpolation.h"
#include "io/trajectoryimport.h"

using namespace geostation;
using geostation::testing::errorOf;
using geostation::testing::freshTestFolder;
namespace fs = std::filesystem;

namespace
{
  //! A van through a bend of 60 m radius at 15 m/s on a 3 % grade, rolling and pitching; t in seconds.
  struct Motion
  {
    Eigen::Vector3d position( double t ) const
    {
      const double theta = 0.25 * t; // v / R
      return Eigen::Vector3d( 560000.0 + 60.0 * std::sin( theta ), 4400000.0 + 60.0 * std::cos( theta ), 200.0 + 0.45 * t );
    }
    //! roll, pitch, heading (degrees); heading from north, clockwise, along the path
    Eigen::Vector3d rollPitchHeadingDeg( double t ) const
    {
      return Eigen::Vector3d( 3.0 * std::sin( 2.0 * t ), 1.7 + 0.5 * std::sin( t ), std::fmod( radToDeg( 0.25 * t ) + 90.0, 360.0 ) );
    }
    Eigen::Matrix3d attitude( double t ) const
    {
      const Eigen::Vector3d a = rollPitchHeadingDeg( t );
      return ( Eigen::AngleAxisd( degToRad( a.z() ), Eigen::Vector3d::UnitZ() ) * Eigen::AngleAxisd( degToRad( a.y() ), Eigen::Vector3d::UnitY() )
               * Eigen::AngleAxisd( degToRad( a.x() ), Eigen::Vector3d::UnitX() ) ).toRotationMatrix();
    }
  };

  std::vector<TrajectoryPose> sampled( const Motion &m, double rateHz, double from, double to )
  {
    std::vector<TrajectoryPose> out;
    for ( int i = 0; from + i / rateHz <= to + 1e-9; ++i )
    {
      const double t = from + i / rateHz;
      out.push_back( { t, m.position( t ), m.attitude( t ) } );
    }
    return out;
  }

  double angleDeg( const Eigen::Matrix3d &a, const Eigen::Matrix3d &b ) { return radToDeg( Eigen::AngleAxisd( a.transpose() * b ).angle() ); }
} // namespace

TEST( TrajectoryInterpolation, PosesThroughABendAtTenAndAHundredHertz )
{
  const Motion motion;
  std::mt19937 rng( 5 );
  std::uniform_real_distribution<double> when( 0.0, 20.0 );
  for ( const double rate : { 10.0, 100.0 } )
  {
    const std::vector<TrajectoryPose> samples = sampled( motion, rate, 0.0, 20.0 );
    const TrajectoryInterpolator trajectory( samples, 1.0 );
    EXPECT_NEAR( trajectory.medianIntervalS(), 1.0 / rate, 1e-12 );
    double worstPosition = 0.0, worstLinear = 0.0, worstAngle = 0.0;
    for ( int k = 0; k < 500; ++k )
    {
      const double t = when( rng );
      const TrajectoryLookup at = trajectory.at( t );
      ASSERT_EQ( at.status, TrajectoryLookup::Status::Interpolated );
      worstPosition = std::max( worstPosition, ( at.pose.position - motion.position( t ) ).norm() );
      worstAngle = std::max( worstAngle, angleDeg( at.pose.attitude, motion.attitude( t ) ) );
      // the straight line between the samples, for comparison
      const size_t i = std::min( samples.size() - 2, static_cast<size_t>( t * rate ) );
      const double s = ( t - samples[i].timeS ) * rate;
      worstLinear = std::max( worstLinear, ( ( 1 - s ) * samples[i].position + s * samples[i + 1].position - motion.position( t ) ).norm() );
    }
    std::printf( "%.0f Hz: position within %.4f mm (straight lines between samples: %.3f mm), attitude within %.5f deg\n", rate, 1e3 * worstPosition, 1e3 * worstLinear,
                 worstAngle );
    if ( rate < 50 )
    {
      EXPECT_LT( worstPosition, 0.1e-3 ); // a 1.5 m step through a 60 m bend
      EXPECT_LT( worstPosition, 0.05 * worstLinear );
      EXPECT_LT( worstAngle, 0.05 ); // the roll's 2 rad/s swing between 0.1 s samples
    }
    else
    {
      EXPECT_LT( worstPosition, 1e-6 );
      EXPECT_LT( worstAngle, 1e-3 );
    }
  }
}

TEST( TrajectoryInterpolation, HeadingThroughNorthGapsAndEnds )
{
  const auto turn = []( double headingDeg ) { return Eigen::Matrix3d( Eigen::AngleAxisd( degToRad( headingDeg ), Eigen::Vector3d::UnitZ() ) ); };
  const TrajectoryInterpolator trajectory( { { 0.0, Eigen::Vector3d( 0, 0, 0 ), turn( 358.0 ) }, { 0.1, Eigen::Vector3d( 1, 0, 0 ), turn( 2.0 ) },
                                             { 0.2, Eigen::Vector3d( 2, 0, 0 ), turn( 6.0 ) }, { 2.0, Eigen::Vector3d( 20, 0, 0 ), turn( 6.0 ) } },
                                           1.0 );
  const TrajectoryLookup north = trajectory.at( 0.05 );
  ASSERT_EQ( north.status, TrajectoryLookup::Status::Interpolated );
  EXPECT_LT( angleDeg( north.pose.attitude, turn( 0.0 ) ), 1e-9 ); // through north, not through south
  EXPECT_NEAR( north.pose.position.x(), 0.5, 1e-12 );
  EXPECT_EQ( trajectory.at( -0.01 ).status, TrajectoryLookup::Status::BeforeStart );
  EXPECT_EQ( trajectory.at( 2.01 ).status, TrajectoryLookup::Status::AfterEnd );
  const TrajectoryLookup gap = trajectory.at( 1.0 );
  EXPECT_EQ( gap.status, TrajectoryLookup::Status::InGap );
  EXPECT_NEAR( gap.gapS, 1.8, 1e-12 );
  EXPECT_EQ( trajectory.at( 0.2 ).status, TrajectoryLookup::Status::Interpolated ); // a sample's own time, before the gap
  // the sample before the gap gets its velocity from the side without it: no overshoot towards the far sample
  EXPECT_NEAR( trajectory.at( 0.15 ).pose.position.x(), 1.5, 1e-9 );

  std::string e = errorOf( [&] { TrajectoryInterpolator( { { 0.0, Eigen::Vector3d::Zero(), turn( 0 ) }, { 0.0, Eigen::Vector3d::Zero(), turn( 0 ) } }, 1.0 ); } );
  EXPECT_NE( e.find( "sample 2 (0.000000 s) does not come after sample 1" ), std::string::npos ) << e;
  e = errorOf( [&] { TrajectoryInterpolator( { { 0.0, Eigen::Vector3d::Zero(), turn( 0 ) } }, 1.0 ); } );
  EXPECT_NE( e.find( "at least 2 samples" ), std::string::npos ) << e;
  e = errorOf( [&] { TrajectoryInterpolator( { { 0.0, Eigen::Vector3d::Zero(), 2.0 * turn( 0 ) }, { 1.0, Eigen::Vector3d::Zero(), turn( 0 ) } }, 1.0 ); } );
  EXPECT_NE( e.find( "not a rotation" ), std::string::npos ) << e;
}

TEST( TrajectoryImport, EventsAreInterpolatedInAHighRateTrajectory )
{
  const fs::path dir = freshTestFolder( "trajectory-events" );
  std::ofstream( dir / "rig.yaml" ) << "%YAML:1.0\n"
                                       "cameras:\n"
                                       "  - id: front\n"
                                       "    image_width: 64\n    image_height: 48\n"
                                       "    camera_matrix: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
                                       "    distortion_coefficients: [ ]\n"
                                       "    lever_arm: [ 1.2, 0.3, -2.1 ]\n"
                                       "    boresight: [ 0.5, -8., 1. ]\n"
                                       "  - id: right\n"
                                       "    image_width: 64\n    image_height: 48\n"
                                       "    camera_matrix: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
                                       "    distortion_coefficients: [ ]\n"
                                       "    lever_arm: [ 0.0, 0.8, -2.0 ]\n"
                                       "    boresight: [ 0., 0., 90. ]\n"
                                       "    image_pattern: \"right/{station}.png\"\n";
  const std::vector<RigCamera> rig = readOpenCvCalibration( dir / "rig.yaml" );
  const Motion motion;
  const double week = 345600.0; // GPS seconds of the week
  // the INS solution at 50 Hz over 0-12 s, with no solution between 8 and 10 s
  {
    std::ofstream csv( dir / "ins.csv" );
    csv << "gps_time,X,Y,Z,roll,pitch,heading\n";
    csv.precision( 12 );
    for ( const TrajectoryPose &p : sampled( motion, 50.0, 0.0, 12.0 ) )
    {
      if ( p.timeS > 8.0 && p.timeS < 10.0 )
        continue;
      const Eigen::Vector3d a = motion.rollPitchHeadingDeg( p.timeS );
      csv << week + p.timeS << "," << p.position.x() << "," << p.position.y() << "," << p.position.z() << "," << a.x() << "," << a.y() << "," << a.z() << "\n";
    }
  }
  // exposures every 0.4 s from -0.587 s (before the solution starts) to 12.213 s (after it ends), and the exact poses at their times
  std::ofstream events( dir / "events.csv" ), exact( dir / "exact.csv" );
  events.precision( 12 );
  exact.precision( 12 );
  events << "time,station,image_front\n";
  exact << "time,station,X,Y,Z,roll,pitch,heading,image_front\n";
  int kept = 0;
  for ( int k = 0; k <= 32; ++k )
  {
    const double t = -0.587 + 0.4 * k;
    char id[16];
    std::snprintf( id, sizeof( id ), "E%02d", k );
    events << week + t << "," << id << ",front/" << id << ".png\n";
    if ( t < 0.0 || t > 12.0 || ( t > 8.0 && t < 10.0 ) )
      continue;
    ++kept;
    const Eigen::Vector3d p = motion.position( t ), a = motion.rollPitchHeadingDeg( t );
    exact << week + t << "," << id << "," << p.x() << "," << p.y() << "," << p.z() << "," << a.x() << "," << a.y() << "," << a.z() << ",front/" << id << ".png\n";
  }
  events.close();
  exact.close();

  TrajectoryImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  options.eventsCsv = dir / "events.csv";
  const BlockImportSummary import = importTrajectory( rig, dir / "ins.csv", options );
  options.eventsCsv.clear();
  const BlockImportSummary truth = importTrajectory( rig, dir / "exact.csv", options );
  ASSERT_EQ( import.block.stations.size(), static_cast<size_t>( kept ) );
  ASSERT_EQ( truth.block.images.size(), import.block.images.size() );
  double worstCentre = 0.0, worstAngle = 0.0;
  for ( size_t i = 0; i < import.block.images.size(); ++i )
  {
    const BlockImage &got = import.block.images[i], &want = truth.block.images[i];
    ASSERT_EQ( got.id, want.id );
    EXPECT_EQ( got.path, want.path );
    worstCentre = std::max( worstCentre, ( got.exterior->projectionCentre - want.exterior->projectionCentre ).norm() );
    worstAngle = std::max( worstAngle, angleDeg( got.exterior->worldFromCamera(), want.exterior->worldFromCamera() ) );
  }
  std::printf( "%zu images at %d events interpolated in a 50 Hz trajectory: centres within %.4f mm, attitudes within %.5f deg of the exact poses\n",
               import.block.images.size(), kept, 1e3 * worstCentre, worstAngle );
  EXPECT_LT( worstCentre, 1e-4 );
  EXPECT_LT( worstAngle, 2e-3 );
  EXPECT_EQ( import.block.images[1].path, "right/" + import.block.stations[0].id + ".png" );
  EXPECT_EQ( import.block.stations[0].id, "E02" );
  // left out and said so: 2 events before the solution, 1 after, 5 in its gap
  EXPECT_EQ( import.dropped.size(), 8u );
  EXPECT_NE( import.dropped.front().find( "outside the trajectory's time span" ), std::string::npos ) << import.dropped.front();
  EXPECT_NE( import.dropped[2].find( "gap of 2 s there (more than 1 s)" ), std::string::npos ) << import.dropped[2];
  ASSERT_FALSE( import.warnings.empty() );
  EXPECT_NE( import.warnings.back().find( "3 event(s) outside the trajectory's time span and 5 in its gaps" ), std::string::npos ) << import.warnings.back();
  bool reported = false;
  for ( const std::string &c : import.converted )
    reported |= c.find( "25 event(s) interpolated in the trajectory's" ) != std::string::npos && c.find( "50.0 Hz" ) != std::string::npos;
  EXPECT_TRUE( reported );

  // one sentence for what cannot be interpolated
  options.eventsCsv = dir / "events.csv";
  std::ofstream( dir / "notime.csv" ) << "X,Y,Z,roll,pitch,heading\n560000,4400000,200,0,0,0\n560001,4400000,200,0,0,0\n";
  std::string e = errorOf( [&] { importTrajectory( rig, dir / "notime.csv", options ); } );
  EXPECT_NE( e.find( "needs a time column" ), std::string::npos ) << e;
  std::ofstream( dir / "backwards.csv" ) << "time,X,Y,Z,roll,pitch,heading\n10,560000,4400000,200,0,0,0\n9,560001,4400000,200,0,0,0\n";
  e = errorOf( [&] { importTrajectory( rig, dir / "backwards.csv", options ); } );
  EXPECT_NE( e.find( "the trajectory's times must increase: sample 2" ), std::string::npos ) << e;
  std::ofstream( dir / "otherclock.csv" ) << "time,X,Y,Z,roll,pitch,heading\n10,560000,4400000,200,0,0,0\n11,560001,4400000,200,0,0,0\n";
  e = errorOf( [&] { importTrajectory( rig, dir / "otherclock.csv", options ); } );
  EXPECT_NE( e.find( "none of the 33 events" ), std::string::npos ) << e;
  EXPECT_NE( e.find( "same clock" ), std::string::npos ) << e;
  std::ofstream( dir / "noeventtime.csv" ) << "station,image_front\nA,a.png\n";
  options.eventsCsv = dir / "noeventtime.csv";
  e = errorOf( [&] { importTrajectory( rig, dir / "ins.csv", options ); } );
  EXPECT_NE( e.find( "the events table needs a time column" ), std::string::npos ) << e;
  fs::remove_all( dir );
}

TEST( TrajectoryImport, IsoTimesOnBothTables )
{
  // a trajectory in UTC and events written with a zone offset: the same instants
  const fs::path dir = freshTestFolder( "trajectory-iso" );
  const RigCamera camera = geostation::testing::forwardRigCamera( "{station}.png" );
  std::ofstream( dir / "ins.csv" ) << "time,X,Y,Z,roll,pitch,heading\n"
                                      "2026-05-04T09:59:59.900Z,560000,4400000,200,0,0,90\n"
                                      "2026-05-04T10:00:00.000Z,560001,4400000,200,0,0,90\n"
                                      "2026-05-04T10:00:00.100Z,560002,4400000,200,0,0,90\n"
                                      "2026-05-04T10:00:00.200Z,560003,4400000,200,0,0,90\n";
  std::ofstream( dir / "events.csv" ) << "time,station\n"
                                         "2026-05-04T11:00:00.050+01:00,A\n"
                                         "2026-05-04 10:00:00.175,B\n"
                                         "2026-05-04T10:00:00.000Z,C\n";
  TrajectoryImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  options.eventsCsv = dir / "events.csv";
  const BlockImportSummary import = importTrajectory( { camera }, dir / "ins.csv", options );
  ASSERT_EQ( import.block.images.size(), 3u );
  EXPECT_EQ( import.block.images[0].path, "A.png" );
  // 10 m/s east, the camera 0 m from the body: X at 0.05 s is 560001.5
  EXPECT_NEAR( import.block.images[0].exterior->projectionCentre.x(), 560001.5, 1e-6 );
  EXPECT_NEAR( import.block.images[1].exterior->projectionCentre.x(), 560002.75, 1e-6 );
  EXPECT_NEAR( import.block.images[2].exterior->projectionCentre.x(), 560001.0, 1e-9 ); // on a sample
  EXPECT_EQ( import.block.stations[0].time, "2026-05-04T11:00:00.050+01:00" );
  std::ofstream( dir / "events.csv" ) << "time,station\nten o'clock,A\n";
  const std::string e = errorOf( [&] { importTrajectory( { camera }, dir / "ins.csv", options ); } );
  EXPECT_NE( e.find( "row 1: \"time\" is \"ten o'clock\", neither seconds nor an ISO 8601 time" ), std::string::npos ) << e;
  fs::remove_all( dir );
}
