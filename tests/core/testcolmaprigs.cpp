// COLMAP 3.12's rigs and frames: read and written exactly (text and binary),
// a rig's frames imported as exposure stations with the rig's geometry
// kept, and bad rigs and frames refused with one sentence.
#include <cmath>
#include <fstream>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "testfiles.h"

#include "geometry/rotation.h"
#include "io/colmapimport.h"
#include "io/stationsequence.h"

using namespace geostation;
using geostation::testing::errorOf;
using geostation::testing::freshTestFolder;
namespace fs = std::filesystem;

namespace
{
  ColmapPose poseOf( const Eigen::Quaterniond &q, const Eigen::Vector3d &t )
  {
    ColmapPose p;
    p.qvec = { q.w(), q.x(), q.y(), q.z() };
    p.tvec = t;
    return p;
  }

  //! The side camera in the rig: looking 90 degrees to the right of the front camera, 0.8 m to its right and 0.3 m behind.
  const Eigen::Isometry3d kSideFromRig = []
  {
    Eigen::Isometry3d rigFromSide = Eigen::Isometry3d::Identity();
    rigFromSide.linear() = Eigen::AngleAxisd( kPi / 2, Eigen::Vector3d::UnitY() ).toRotationMatrix();
    rigFromSide.translation() = Eigen::Vector3d( 0.8, 0.0, -0.3 );
    return rigFromSide.inverse();
  }();

  /**
   * A van's run as COLMAP 3.12 stores it: a rig of a front camera (the
   * reference), a side camera and an IMU; five frames along a gently
   * curving track, each with both cameras' images and an IMU record; the
   * images' poses composed from the frame's and the side camera's pose in
   * the rig, as COLMAP writes them.
   */
  ColmapModel rigModel()
  {
    ColmapModel m;
    m.cameras.push_back( { 1, "OPENCV", 1200, 900, { 1010.5, 1012.25, 601.3, 449.8, -0.08, 0.012, 0.0004, -0.0003 } } );
    m.cameras.push_back( { 2, "PINHOLE", 800, 600, { 700.0, 701.0, 399.5, 300.25 } } );
    ColmapRig rig;
    rig.id = 1;
    rig.reference = ColmapSensor { ColmapSensor::Type::Camera, 1 };
    const Eigen::Quaterniond sideRotation( kSideFromRig.linear() );
    rig.others.push_back( { { ColmapSensor::Type::Camera, 2 }, poseOf( sideRotation, kSideFromRig.translation() ) } );
    rig.others.push_back( { { ColmapSensor::Type::Imu, 1 }, std::nullopt } );
    m.rigs.push_back( rig );
    for ( std::uint32_t f = 0; f < 5; ++f )
    {
      // the rig (front camera: x right, y down, z ahead) driving along the model's x, turning slowly
      const double heading = 0.05 * f;
      const Eigen::Matrix3d worldFromRig = Eigen::AngleAxisd( heading, Eigen::Vector3d::UnitZ() ).toRotationMatrix()
                                           * ( Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0 ).finished();
      const Eigen::Vector3d centre( 6.0 * f, 0.4 * f * f, 2.5 );
      Eigen::Isometry3d rigFromWorld = Eigen::Isometry3d::Identity();
      rigFromWorld.linear() = worldFromRig.transpose();
      rigFromWorld.translation() = -worldFromRig.transpose() * centre;
      ColmapFrame frame;
      frame.id = 1 + f;
      frame.rigId = 1;
      frame.rigFromWorld = poseOf( Eigen::Quaterniond( rigFromWorld.linear() ), rigFromWorld.translation() );
      const char *folders[] = { "front", "side" };
      for ( std::uint32_t camera = 1; camera <= 2; ++camera )
      {
        const Eigen::Isometry3d camFromWorld = camera == 1 ? rigFromWorld : kSideFromRig * rigFromWorld;
        ColmapImage im;
        im.id = 100 * camera + f;
        im.cameraId = camera;
        im.name = std::string( folders[camera - 1] ) + "/000" + std::to_string( f ) + ".jpg";
        const ColmapPose pose = poseOf( Eigen::Quaterniond( camFromWorld.linear() ), camFromWorld.translation() );
        im.qvec = pose.qvec;
        im.tvec = pose.tvec;
        m.images.push_back( im );
        frame.data.push_back( { { ColmapSensor::Type::Camera, camera }, im.id } );
      }
      frame.data.push_back( { { ColmapSensor::Type::Imu, 1 }, 9000 + f } );
      m.frames.push_back( frame );
    }
    return m;
  }

  void expectSamePose( const ColmapPose &a, const ColmapPose &b )
  {
    EXPECT_EQ( a.qvec, b.qvec );
    EXPECT_EQ( a.tvec, b.tvec );
  }

  void expectSameRigsAndFrames( const ColmapModel &a, const ColmapModel &b )
  {
    ASSERT_EQ( a.rigs.size(), b.rigs.size() );
    for ( size_t i = 0; i < a.rigs.size(); ++i )
    {
      EXPECT_EQ( a.rigs[i].id, b.rigs[i].id );
      ASSERT_EQ( a.rigs[i].reference.has_value(), b.rigs[i].reference.has_value() );
      if ( a.rigs[i].reference )
      {
        EXPECT_TRUE( *a.rigs[i].reference == *b.rigs[i].reference );
      }
      ASSERT_EQ( a.rigs[i].others.size(), b.rigs[i].others.size() );
      for ( size_t k = 0; k < a.rigs[i].others.size(); ++k )
      {
        EXPECT_TRUE( a.rigs[i].others[k].sensor == b.rigs[i].others[k].sensor );
        ASSERT_EQ( a.rigs[i].others[k].sensorFromRig.has_value(), b.rigs[i].others[k].sensorFromRig.has_value() );
        if ( a.rigs[i].others[k].sensorFromRig )
          expectSamePose( *a.rigs[i].others[k].sensorFromRig, *b.rigs[i].others[k].sensorFromRig );
      }
    }
    ASSERT_EQ( a.frames.size(), b.frames.size() );
    for ( size_t i = 0; i < a.frames.size(); ++i )
    {
      EXPECT_EQ( a.frames[i].id, b.frames[i].id );
      EXPECT_EQ( a.frames[i].rigId, b.frames[i].rigId );
      expectSamePose( a.frames[i].rigFromWorld, b.frames[i].rigFromWorld );
      ASSERT_EQ( a.frames[i].data.size(), b.frames[i].data.size() );
      for ( size_t k = 0; k < a.frames[i].data.size(); ++k )
      {
        EXPECT_TRUE( a.frames[i].data[k].sensor == b.frames[i].data[k].sensor );
        EXPECT_EQ( a.frames[i].data[k].dataId, b.frames[i].data[k].dataId );
      }
    }
  }

  ColmapImportOptions noFiles()
  {
    ColmapImportOptions o;
    o.crs = "EPSG:32617";
    o.requireImageFiles = false;
    return o;
  }

  bool hasSentence( const std::vector<std::string> &sentences, const std::string &part )
  {
    for ( const std::string &s : sentences )
      if ( s.find( part ) != std::string::npos )
        return true;
    return false;
  }
} // namespace

TEST( ColmapRigs, TextAndBinaryRoundTripExactly )
{
  const ColmapModel model = rigModel();
  const fs::path dir = freshTestFolder( "colmap-rigs-roundtrip" );
  model.writeText( dir / "text" );
  model.writeBinary( dir / "bin" );
  EXPECT_TRUE( fs::exists( dir / "text" / "frames.txt" ) );
  EXPECT_TRUE( fs::exists( dir / "bin" / "rigs.bin" ) );
  expectSameRigsAndFrames( model, ColmapModel::read( dir / "text" ) );
  expectSameRigsAndFrames( model, ColmapModel::read( dir / "bin" / "frames.bin" ) );
  // binary sizes as COLMAP lays them out: rigs 8 + 4 + 4 + 8 + (4 + 4 + 1 + 56) + (4 + 4 + 1); frames 8 + 5 x (68 + 3 x 16)
  EXPECT_EQ( fs::file_size( dir / "bin" / "rigs.bin" ), 8u + 4 + 4 + 8 + 65 + 9 );
  EXPECT_EQ( fs::file_size( dir / "bin" / "frames.bin" ), 8u + 5 * ( 68 + 3 * 16 ) );
  // a model without rigs written over it leaves no stale rigs or frames behind
  ColmapModel older = model;
  older.rigs.clear();
  older.frames.clear();
  older.writeBinary( dir / "bin" );
  const ColmapModel reread = ColmapModel::read( dir / "bin" );
  EXPECT_TRUE( reread.rigs.empty() );
  EXPECT_TRUE( reread.frames.empty() );
  fs::remove_all( dir );
}

TEST( ColmapRigs, FramesBecomeExposureStationsWithTheRigsGeometry )
{
  const ColmapModel model = rigModel();
  const fs::path dir = freshTestFolder( "colmap-rigs-import" );
  model.writeBinary( dir / "sparse" );
  const BlockImportSummary import = importColmapModel( ColmapModel::read( dir / "sparse" ), dir / "sparse", noFiles() );
  const Block &block = import.block;
  ASSERT_EQ( block.images.size(), 10u );
  ASSERT_EQ( block.stations.size(), 5u );
  EXPECT_TRUE( hasSentence( import.converted, "10 registered image(s) became oriented images in 5 exposure station(s)" ) );
  EXPECT_TRUE( hasSentence( import.converted, "5 frame(s) of COLMAP rig 1, reference CAMERA 1, 3 sensor(s) became exposure stations of up to 2 image(s)" ) );
  EXPECT_TRUE( import.warnings.empty() );

  // the run in order, each station named after its front image and holding both cameras' images
  const StationSequence run( block );
  ASSERT_EQ( run.size(), 5 );
  for ( int f = 0; f < 5; ++f )
  {
    const SequenceStation &station = run.at( f );
    EXPECT_EQ( station.id, "front/000" + std::to_string( f ) );
    ASSERT_EQ( station.imageIds.size(), 2u );
    const BlockImage *front = nullptr, *side = nullptr;
    for ( const BlockImage &image : block.images )
    {
      if ( image.id == "front/000" + std::to_string( f ) )
        front = &image;
      if ( image.id == "side/000" + std::to_string( f ) )
        side = &image;
    }
    ASSERT_TRUE( front && side );
    EXPECT_EQ( front->stationId, station.id );
    EXPECT_EQ( side->stationId, station.id );
    // the rig's geometry survives the conversion: the side camera 0.85 m from the front one, turned 90 degrees
    const Eigen::Vector3d offset = side->exterior->projectionCentre - front->exterior->projectionCentre;
    EXPECT_NEAR( offset.norm(), std::hypot( 0.8, 0.3 ), 1e-9 );
    const Eigen::Matrix3d frontFromSide = front->exterior->worldFromCamera().transpose() * side->exterior->worldFromCamera();
    EXPECT_NEAR( Eigen::AngleAxisd( frontFromSide ).angle(), kPi / 2, 1e-9 );
    // and the side camera lies to the front camera's right (+x of its image), 0.3 m behind it
    const Eigen::Vector3d inFront = front->exterior->worldFromCamera().transpose() * offset;
    EXPECT_NEAR( std::abs( inFront.x() ), 0.8, 1e-9 );
    EXPECT_NEAR( std::abs( inFront.z() ), 0.3, 1e-9 );
  }
  fs::remove_all( dir );
}

TEST( ColmapRigs, AnImageInNoFrameIsAStationOfItsOwn )
{
  ColmapModel model = rigModel();
  model.frames.back().data.erase( model.frames.back().data.begin() + 1 ); // side/0004 left out of its frame
  const fs::path dir = freshTestFolder( "colmap-rigs-alone" );
  model.writeText( dir );
  const BlockImportSummary import = importColmapModel( model, dir, noFiles() );
  EXPECT_EQ( import.block.stations.size(), 6u );
  EXPECT_TRUE( hasSentence( import.warnings, "1 image(s) are in no COLMAP frame; each became a station of its own" ) );
  for ( const BlockImage &image : import.block.images )
    if ( image.id == "side/0004" )
    {
      EXPECT_EQ( image.stationId, "side/0004" );
    }
  // a frame naming an image the model does not hold is reported, not fatal
  model.frames.front().data.push_back( { { ColmapSensor::Type::Camera, 2 }, 777 } );
  EXPECT_TRUE( hasSentence( importColmapModel( model, dir, noFiles() ).dropped, "1 image(s) named by the COLMAP frames are not in the model's images" ) );
  fs::remove_all( dir );
}

TEST( ColmapRigs, BadRigsAndFramesAreRefusedWithOneSentence )
{
  const fs::path dir = freshTestFolder( "colmap-rigs-bad" );
  const ColmapModel model = rigModel();
  model.writeBinary( dir / "bin" );
  {
    const fs::path f = dir / "bin" / "frames.bin";
    fs::resize_file( f, fs::file_size( f ) - 20 );
    const std::string e = errorOf( [&] { ColmapModel::read( dir / "bin" ); } );
    EXPECT_NE( e.find( "frames.bin" ), std::string::npos ) << e;
    EXPECT_NE( e.find( "truncated" ), std::string::npos ) << e;
  }
  {
    // a sensor type COLMAP does not have
    std::ofstream out( dir / "bin" / "rigs.bin", std::ios::binary );
    const std::uint64_t n = 1;
    const std::uint32_t id = 1, sensors = 1;
    const std::int32_t type = 7;
    out.write( reinterpret_cast<const char *>( &n ), 8 );
    out.write( reinterpret_cast<const char *>( &id ), 4 );
    out.write( reinterpret_cast<const char *>( &sensors ), 4 );
    out.write( reinterpret_cast<const char *>( &type ), 4 );
    out.write( reinterpret_cast<const char *>( &id ), 4 );
    out.close();
    const std::string e = errorOf( [&] { ColmapModel::read( dir / "bin" ); } );
    EXPECT_NE( e.find( "rigs.bin, rig 1: the sensor type 7" ), std::string::npos ) << e;
  }
  model.writeText( dir / "txt" );
  {
    std::ofstream( dir / "txt" / "frames.txt" ) << "# frames\n1 1 1 0 0 0 0 0 0 1 LIDAR 1 100\n";
    const std::string e = errorOf( [&] { ColmapModel::read( dir / "txt" ); } );
    EXPECT_NE( e.find( "frames.txt, line 2: the sensor type 'LIDAR'" ), std::string::npos ) << e;
    std::ofstream( dir / "txt" / "frames.txt" ) << "1 1 1 0 0 0 0 0 0 2 CAMERA 1 100\n";
    EXPECT_NE( errorOf( [&] { ColmapModel::read( dir / "txt" ); } ).find( "frames.txt, line 1: expected SENSOR_TYPE" ), std::string::npos );
    std::ofstream( dir / "txt" / "rigs.txt" ) << "1 2 CAMERA 1 CAMERA 2 2\n";
    EXPECT_NE( errorOf( [&] { ColmapModel::read( dir / "txt" ); } ).find( "rigs.txt, line 1: HAS_POSE is 2 (0 or 1)" ), std::string::npos );
  }
  {
    // an image in two frames, and a frame that names the wrong camera
    rigModel().writeText( dir );
    ColmapModel twice = rigModel();
    twice.frames[1].data.push_back( twice.frames[0].data[0] );
    EXPECT_NE( errorOf( [&] { importColmapModel( twice, dir, noFiles() ); } ).find( "image 100 is in frame 1 and in frame 2" ), std::string::npos );
    ColmapModel wrongCamera = rigModel();
    wrongCamera.frames[2].data[1].sensor.id = 1;
    EXPECT_NE( errorOf( [&] { importColmapModel( wrongCamera, dir, noFiles() ); } ).find( "frame 3 says image 202 (side/0002.jpg) was taken by camera 1, the image says camera 2" ),
               std::string::npos );
  }
  fs::remove_all( dir );
}
