// The mapping-van case: OpenCV calibration files (one camera or a rig with
// lever arms, boresights and image patterns) plus a trajectory CSV, checked
// against physical facts (which way a camera looks for a given heading,
// pitch, roll and boresight; meridian convergence), and bad tables refused
// with one sentence; NaN and infinity refused by every reader of numbers
// from outside.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "rigcameras.h"
#include "testfiles.h"
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>

#include "geometry/crs.h"
#include "geometry/projection.h"
#include "geometry/rotation.h"
#include "io/block.h"
#include "io/colmapmodel.h"
#include "io/metashapeimport.h"
#include "io/trajectoryimport.h"

using namespace geostation;
using geostation::testing::errorOf;
using geostation::testing::freshTestFolder;
namespace fs = std::filesystem;

namespace
{
  RigCamera forwardCamera() { return geostation::testing::forwardRigCamera(); }

  Eigen::Vector3d axis( const Eigen::Matrix3d &worldFromCamera, int column ) { return worldFromCamera.col( column ); }
  Eigen::Vector3d viewing( const Eigen::Matrix3d &worldFromCamera ) { return -worldFromCamera.col( 2 ); }

  void writeImage( const fs::path &file, int width, int height )
  {
    fs::create_directories( file.parent_path() );
    ASSERT_TRUE( cv::imwrite( file.string(), cv::Mat( height, width, CV_8UC1, cv::Scalar( 128 ) ) ) );
  }
} // namespace

TEST( OpenCvCalibration, CameraMatrixAndDistortionConvertExactly )
{
  const fs::path dir = freshTestFolder( "trajectory-calib" );
  {
    cv::FileStorage out( ( dir / "front.yaml" ).string(), cv::FileStorage::WRITE );
    out << "image_width" << 1920 << "image_height" << 1080;
    out << "camera_matrix" << ( cv::Mat_<double>( 3, 3 ) << 1400.5, 0, 959.25, 0, 1401.0, 539.75, 0, 0, 1 );
    out << "distortion_coefficients" << ( cv::Mat_<double>( 1, 5 ) << -0.21, 0.05, 0.001, -0.0005, 0.002 );
  }
  const std::vector<RigCamera> cameras = readOpenCvCalibration( dir / "front.yaml" );
  ASSERT_EQ( cameras.size(), 1u );
  const Camera &c = cameras[0].camera;
  EXPECT_EQ( c.id, "front" );
  EXPECT_EQ( c.width, 1920 );
  EXPECT_EQ( c.f, 1400.5 );
  EXPECT_DOUBLE_EQ( c.aspect, 1401.0 / 1400.5 );
  EXPECT_EQ( c.cx, 959.75 ); // OpenCV's pixel centres are integers
  EXPECT_EQ( c.cy, 540.25 );
  EXPECT_EQ( c.distortion.model, DistortionModel::OpenCV );
  EXPECT_EQ( c.distortion.k3(), 0.002 );
  EXPECT_TRUE( isOpenCvCalibration( dir / "front.yaml" ) );

  // the same calibration in XML, with OpenCV's 8 coefficients and a rational term
  {
    cv::FileStorage out( ( dir / "rational.xml" ).string(), cv::FileStorage::WRITE );
    out << "image_width" << 640 << "image_height" << 480;
    out << "camera_matrix" << ( cv::Mat_<double>( 3, 3 ) << 500, 0, 319.5, 0, 500, 239.5, 0, 0, 1 );
    out << "distortion_coefficients" << ( cv::Mat_<double>( 8, 1 ) << -0.1, 0.01, 0, 0, 0, 0.02, 0, 0 );
  }
  EXPECT_NE( errorOf( [&] { readOpenCvCalibration( dir / "rational.xml" ); } ).find( "rational, thin-prism or tilt" ), std::string::npos );
  EXPECT_NE( errorOf( [&] { cameraFromOpenCv( "s", ( Eigen::Matrix3d() << 500, 1, 320, 0, 500, 240, 0, 0, 1 ).finished(), {}, 640, 480 ); } ).find( "skew" ), std::string::npos );
  std::ofstream( dir / "notes.yaml" ) << "%YAML:1.0\nsomething: 1\n";
  EXPECT_NE( errorOf( [&] { readOpenCvCalibration( dir / "notes.yaml" ); } ).find( "neither \"camera_matrix\"" ), std::string::npos );
  EXPECT_FALSE( isOpenCvCalibration( dir / "notes.yaml" ) );
  fs::remove_all( dir );
}

TEST( TrajectoryImport, CamerasLookWhereHeadingPitchRollAndBoresightSay )
{
  const RigCamera front = forwardCamera();
  // heading 0 (north), level: looking north, image right east, image up up: omega 90, phi 0, kappa 0
  const Eigen::Matrix3d north = worldFromRigCamera( { 0, 0, 0 }, front, 0.0 );
  EXPECT_LT( ( north - worldFromCameraRotationDeg( 90, 0, 0 ) ).cwiseAbs().maxCoeff(), 1e-15 );
  // heading 90: looking east, image right south
  const Eigen::Matrix3d east = worldFromRigCamera( { 0, 0, 90 }, front, 0.0 );
  EXPECT_LT( ( viewing( east ) - Eigen::Vector3d( 1, 0, 0 ) ).norm(), 1e-15 );
  EXPECT_LT( ( axis( east, 0 ) - Eigen::Vector3d( 0, -1, 0 ) ).norm(), 1e-15 );
  // pitch +10: the nose and the view go up
  EXPECT_NEAR( viewing( worldFromRigCamera( { 0, 10, 0 }, front, 0.0 ) ).z(), std::sin( degToRad( 10 ) ), 1e-15 );
  // roll +10: the right side goes down, so does image right
  EXPECT_NEAR( axis( worldFromRigCamera( { 10, 0, 0 }, front, 0.0 ), 0 ).z(), -std::sin( degToRad( 10 ) ), 1e-15 );
  // a camera mounted looking right (boresight heading 90) on a van heading north looks east
  RigCamera right = front;
  right.boresightDeg = { 0, 0, 90 };
  EXPECT_LT( ( viewing( worldFromRigCamera( { 0, 0, 0 }, right, 0.0 ) ) - Eigen::Vector3d( 1, 0, 0 ) ).norm(), 1e-15 );
  // a camera pitched down 30 degrees looks 30 degrees below the horizon
  RigCamera down = front;
  down.boresightDeg = { 0, -30, 0 };
  EXPECT_NEAR( viewing( worldFromRigCamera( { 0, 0, 45 }, down, 0.0 ) ).z(), -0.5, 1e-15 );
  // the lever arm is in the body frame: 1 m forward of a van heading east is 1 m east
  EXPECT_LT( ( worldFromBody( { 0, 0, 90 }, 0.0 ) * Eigen::Vector3d( 1, 0, 0 ) - Eigen::Vector3d( 1, 0, 0 ) ).norm(), 1e-15 );
  EXPECT_LT( ( worldFromBody( { 0, 0, 90 }, 0.0 ) * Eigen::Vector3d( 0, 0, -1.5 ) - Eigen::Vector3d( 0, 0, 1.5 ) ).norm(), 1e-15 ); // z down
}

TEST( TrajectoryImport, RigAndTrajectoryBecomeABlockWithConvergence )
{
  const fs::path dir = freshTestFolder( "trajectory-rig" );
  std::ofstream( dir / "rig.yaml" ) << "%YAML:1.0\n"
                                       "cameras:\n"
                                       "  - id: front\n"
                                       "    image_width: 64\n    image_height: 48\n"
                                       "    camera_matrix: !!opencv-matrix\n      rows: 3\n      cols: 3\n      dt: d\n      data: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
                                       "    distortion_coefficients: [ -0.1, 0.01, 0., 0. ]\n"
                                       "    lever_arm: [ 1.0, 0.0, -2.0 ]\n"
                                       "    boresight: [ 0., -10., 0. ]\n"
                                       "    image_pattern: \"img/{station}_front.png\"\n"
                                       "  - id: right\n"
                                       "    image_width: 64\n    image_height: 48\n"
                                       "    camera_matrix: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
                                       "    distortion_coefficients: [ ]\n"
                                       "    lever_arm: [ 0.0, 0.8, -2.0 ]\n"
                                       "    boresight: [ 0., 0., 90. ]\n";
  const std::vector<RigCamera> rig = readOpenCvCalibration( dir / "rig.yaml" );
  ASSERT_EQ( rig.size(), 2u );
  EXPECT_EQ( rig[0].leverArmM, Eigen::Vector3d( 1, 0, -2 ) );
  EXPECT_EQ( rig[1].camera.distortion.model, DistortionModel::None );

  // three rows at 40 N, 78 W: three degrees east of UTM 17's central meridian
  std::ofstream( dir / "trajectory.csv" ) << "time,station,latitude,longitude,height,roll,pitch,heading,image_right\n"
                                             "2025-05-01T10:00:00.0Z,P1,40.0,-78.0,200.0,0,0,0,img/right_1.png\n"
                                             "2025-05-01T10:00:01.0Z,P2,40.0001,-78.0,200.1,0,0,0,img/right_2.png\n"
                                             "2025-05-01T10:00:02.0Z,P3,40.0002,-78.0,200.2,1.5,-0.5,10,img/right_3.png\n";
  for ( const char *name : { "img/P1_front.png", "img/P2_front.png", "img/P3_front.png", "img/right_1.png", "img/right_2.png", "img/right_3.png" } )
    writeImage( dir / name, 64, 48 );
  TrajectoryImportOptions options;
  options.crs = "EPSG:32617";
  const BlockImportSummary import = importTrajectory( rig, dir / "trajectory.csv", options );
  ASSERT_EQ( import.block.stations.size(), 3u );
  ASSERT_EQ( import.block.images.size(), 6u );
  EXPECT_EQ( import.block.stations[0].time, "2025-05-01T10:00:00.0Z" );
  EXPECT_EQ( import.block.images[0].id, "P1_front" );
  EXPECT_EQ( import.block.images[0].path, "img/P1_front.png" );
  EXPECT_EQ( import.block.images[1].path, "img/right_1.png" );
  EXPECT_EQ( import.block.images[1].stationId, "P1" );

  // heading 0 is true north; in UTM 17 at 78 W the grid azimuth of true north
  // is -gamma with gamma = atan(tan(dlon) sin(lat)) (convergence, 1.93 deg)
  const double gamma = radToDeg( std::atan( std::tan( degToRad( 3.0 ) ) * std::sin( degToRad( 40.0 ) ) ) );
  const ExteriorOrientation &front = *import.block.images[0].exterior;
  const Eigen::Vector3d v = front.viewingDirection();
  EXPECT_NEAR( radToDeg( std::atan2( v.x(), v.y() ) ), -gamma, 0.01 );
  EXPECT_NEAR( radToDeg( std::asin( v.z() ) ), -10.0, 1e-9 ); // boresight pitch -10
  // the lever arm: 1 m forward (true north) and 2 m up from the trajectory point
  CrsTransform toUtm( "EPSG:4326", "EPSG:32617" );
  const Eigen::Vector3d p1 = toUtm.transform( { -78.0, 40.0, 200.0 } );
  const Eigen::Vector3d offset = front.projectionCentre - p1;
  EXPECT_NEAR( offset.z(), 2.0, 1e-9 );
  EXPECT_NEAR( offset.head<2>().norm(), 1.0, 1e-9 );
  EXPECT_NEAR( radToDeg( std::atan2( offset.x(), offset.y() ) ), -gamma, 0.01 );
  // the right camera looks east (grid azimuth 90 - gamma)
  const Eigen::Vector3d r = import.block.images[1].exterior->viewingDirection();
  EXPECT_NEAR( radToDeg( std::atan2( r.x(), r.y() ) ), 90.0 - gamma, 0.01 );
  EXPECT_NE( import.converted.back().find( "meridian convergence" ), std::string::npos );

  // a point 20 m straight ahead of the level front camera, 20 tan(10) below its axis... on the axis: the principal point
  const OrientedImage oriented( import.block.cameras[0], front );
  const GroundProjection g = oriented.projectGroundToPixel( front.projectionCentre + 20.0 * v );
  EXPECT_LT( ( g.pixelInImage - Eigen::Vector2d( 32.0, 24.0 ) ).norm(), 1e-9 );
  fs::remove_all( dir );
}

TEST( TrajectoryImport, OneCameraWithItsOwnOrientationPerRow )
{
  const fs::path dir = freshTestFolder( "trajectory-eo" );
  std::ofstream( dir / "eo.csv" ) << "image;X;Y;Z;omega;phi;kappa\n"
                                     "a.png;500100.25;4400200.5;310.0;0.5;-0.25;91.0\n"
                                     "b.png;500150.25;4400200.5;311.0;0.25;0.5;-179.5\n";
  writeImage( dir / "a.png", 64, 48 );
  writeImage( dir / "b.png", 64, 48 );
  TrajectoryImportOptions options;
  options.crs = "EPSG:32617";
  const BlockImportSummary import = importTrajectory( { forwardCamera() }, dir / "eo.csv", options );
  ASSERT_EQ( import.block.images.size(), 2u );
  const ExteriorOrientation &b = *import.block.images[1].exterior;
  EXPECT_EQ( import.block.images[1].id, "S0002" );
  EXPECT_EQ( b.projectionCentre, Eigen::Vector3d( 500150.25, 4400200.5, 311.0 ) );
  EXPECT_NEAR( b.omegaDeg, 0.25, 1e-12 );
  EXPECT_NEAR( b.phiDeg, 0.5, 1e-12 );
  EXPECT_NEAR( b.kappaDeg, -179.5, 1e-12 );
  fs::remove_all( dir );
}

TEST( TrajectoryImport, BadTablesAreRefusedWithOneSentence )
{
  const fs::path dir = freshTestFolder( "trajectory-bad" );
  TrajectoryImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  RigCamera camera = forwardCamera();
  camera.imagePattern = "{station}.png";
  auto importText = [&]( const std::string &text, const std::vector<RigCamera> &rig ) {
    std::ofstream( dir / "t.csv" ) << text;
    return errorOf( [&] { importTrajectory( rig, dir / "t.csv", options ); } );
  };
  std::string e = importText( "t,e,n,u,r,p,y\n1,2,3,4,5,6,7\n", { camera } );
  EXPECT_NE( e.find( "no position columns: expected X, Y, Z" ), std::string::npos ) << e;
  EXPECT_NE( e.find( "(the table has: t, e, n, u, r, p, y)" ), std::string::npos ) << e;
  e = importText( "X,Y,Z,a,b,c\n1,2,3,4,5,6\n", { camera } );
  EXPECT_NE( e.find( "no attitude columns" ), std::string::npos ) << e;
  e = importText( "X,Y,Z,roll,pitch,heading\n1,2,3,0,0,north\n", { camera } );
  EXPECT_NE( e.find( "row 1: \"heading\" is \"north\", not a number" ), std::string::npos ) << e;

  // radians given where degrees are read: every angle tiny, the heading turning by 1.5
  std::string radians = "X,Y,Z,roll,pitch,heading\n";
  for ( int i = 0; i < 12; ++i )
    radians += std::to_string( 500000 + 5 * i ) + ",4400000,200,0.01,-0.02," + std::to_string( 0.1 + 0.125 * i ) + "\n";
  e = importText( radians, { camera } );
  EXPECT_NE( e.find( "look like radians" ), std::string::npos ) << e;
  options.anglesInRadians = true;
  EXPECT_EQ( importText( radians, { camera } ), "(no error)" );
  options.anglesInRadians = false;

  RigCamera other = camera;
  other.camera.id = "other";
  other.imagePattern.clear();
  e = importText( "X,Y,Z,roll,pitch,heading\n1,2,3,0,0,0\n", { camera, other } );
  EXPECT_NE( e.find( "camera \"other\" has no image names: give the table a column \"image_other\"" ), std::string::npos ) << e;
  e = importText( "X,Y,Z,omega,phi,kappa,image\n1,2,3,0,0,0,a.png\n", { camera, other } );
  EXPECT_NE( e.find( "omega, phi, kappa are one camera's orientation" ), std::string::npos ) << e;

  options.requireImageFiles = true;
  e = importText( "X,Y,Z,roll,pitch,heading\n500000,4400000,200,0,0,0\n", { camera } );
  EXPECT_NE( e.find( "does not exist" ), std::string::npos ) << e;
  EXPECT_NE( e.find( "(image names resolve in" ), std::string::npos ) << e;
  fs::remove_all( dir );
}

TEST( ImportedTables, NotANumberAndInfinityAreRefusedByEveryReader )
{
  const fs::path dir = freshTestFolder( "not-a-number" );
  TrajectoryImportOptions trajectory;
  trajectory.crs = "EPSG:32617";
  trajectory.requireImageFiles = false;
  RigCamera camera = forwardCamera();
  camera.imagePattern = "{station}.png";
  for ( const std::string value : { "nan", "NaN", "inf", "-inf", "Infinity", "1e999" } )
  {
    SCOPED_TRACE( value );
    // a trajectory table
    std::ofstream( dir / "t.csv" ) << "X,Y,Z,roll,pitch,heading\n500000,4400000," << value << ",0,0,0\n";
    std::string e = errorOf( [&] { importTrajectory( { camera }, dir / "t.csv", trajectory ); } );
    EXPECT_NE( e.find( "\"Z\" is \"" + value + "\", not a number" ), std::string::npos ) << e;
    // an OpenCV calibration (YAML spells them .nan and .inf; both kinds are tried)
    std::ofstream( dir / "c.yaml" ) << "%YAML:1.0\nimage_width: 64\nimage_height: 48\ncamera_matrix: [ 50., 0., 31.5, 0., " << ( value == "nan" ? ".nan" : value == "inf" ? ".inf" : value )
                                    << ", 23.5, 0., 0., 1. ]\ndistortion_coefficients: [ ]\n";
    e = errorOf( [&] { readOpenCvCalibration( dir / "c.yaml" ); } );
    EXPECT_NE( e.find( "the calibration file" ), std::string::npos ) << e;
    // a COLMAP model
    fs::create_directories( dir / "colmap" );
    std::ofstream( dir / "colmap" / "cameras.txt" ) << "1 PINHOLE 64 48 50 50 32 24\n";
    std::ofstream( dir / "colmap" / "images.txt" ) << "1 1 0 0 0 " << value << " 0 0 1 a.png\n\n";
    e = errorOf( [&] { ColmapModel::read( dir / "colmap" ); } );
    EXPECT_NE( e.find( "images.txt, line 1: expected TX TY TZ" ), std::string::npos ) << e;
    // a Metashape camera file
    std::ofstream( dir / "m.xml" ) << "<document><chunk><sensors><sensor id=\"0\" type=\"frame\"><resolution width=\"60\" height=\"40\"/>"
                                      "<calibration type=\"frame\"><resolution width=\"60\" height=\"40\"/><f>50</f></calibration></sensor></sensors>"
                                      "<cameras><camera id=\"0\" sensor_id=\"0\" label=\"a\"><transform>1 0 0 "
                                   << value << " 0 1 0 0 0 0 1 0 0 0 0 1</transform></camera></cameras></chunk></document>\n";
    MetashapeImportOptions metashape;
    metashape.crs = "EPSG:32617";
    metashape.requireImageFiles = false;
    e = errorOf( [&] { importMetashapeCameras( dir / "m.xml", metashape ); } );
    EXPECT_NE( e.find( "holds something that is not a number" ), std::string::npos ) << e;
    // a block file (JSON has no NaN; a number too large is the way in)
    e = errorOf( [&] { Block::fromJsonText( "{\"format\": \"geostation-block\", \"version\": 1, \"crs\": \"EPSG:32617\", \"cameras\": [{\"id\": \"c\", "
                                             "\"width\": 64, \"height\": 48, \"f\": " + std::string( value == "-inf" ? "-1e999" : "1e999" ) + ", \"cx\": 32, \"cy\": 24}], \"images\": []}",
                                             dir / "b.geostation.json" ); } );
    EXPECT_NE( e.find( "not valid JSON: a number is too large to be read" ), std::string::npos ) << e;
  }
  fs::remove_all( dir );
}
