// COLMAP sparse models: text and binary read/write, camera and pose
// conversion checked against COLMAP's own projection equations, import with
// dropped cameras reported, georeferencing by camera centres and control
// points, export -> import round trips, and bad models refused with one
// sentence.
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "testfiles.h"

#include "geometry/projection.h"
#include "geometry/rotation.h"
#include "geometry/similaritytransform.h"
#include "io/blockexport.h"
#include "io/colmapconversion.h"
#include "io/colmapimport.h"

using namespace geostation;
using geostation::testing::errorOf;
using geostation::testing::freshTestFolder;
namespace fs = std::filesystem;

namespace
{
  const char *kCrs = "EPSG:32617";

  /**
   * COLMAP's WorldToImage, written from COLMAP's camera_models.h: camFromWorld,
   * perspective division (camera looks along +z), the model's distortion on
   * normalised coordinates, then focal length and principal point.
   */
  Eigen::Vector2d colmapProject( const ColmapCamera &c, const ColmapImage &im, const Eigen::Vector3d &world )
  {
    const Eigen::Quaterniond q( im.qvec[0], im.qvec[1], im.qvec[2], im.qvec[3] );
    const Eigen::Vector3d x = q.normalized().toRotationMatrix() * world + im.tvec;
    const double u = x.x() / x.z(), v = x.y() / x.z();
    const std::vector<double> &p = c.params;
    double fx, fy, cx, cy, k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
    if ( c.model == "SIMPLE_PINHOLE" || c.model == "SIMPLE_RADIAL" || c.model == "RADIAL" )
    {
      fx = fy = p[0];
      cx = p[1];
      cy = p[2];
      if ( c.model != "SIMPLE_PINHOLE" )
        k1 = p[3];
      if ( c.model == "RADIAL" )
        k2 = p[4];
    }
    else
    {
      fx = p[0];
      fy = p[1];
      cx = p[2];
      cy = p[3];
      if ( c.model != "PINHOLE" )
      {
        k1 = p[4];
        k2 = p[5];
        p1 = p[6];
        p2 = p[7];
      }
      if ( c.model == "FULL_OPENCV" )
        k3 = p[8];
    }
    const double u2 = u * u, uv = u * v, v2 = v * v, r2 = u2 + v2;
    const double radial = k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
    const double du = u * radial + 2 * p1 * uv + p2 * ( r2 + 2 * u2 );
    const double dv = v * radial + 2 * p2 * uv + p1 * ( r2 + 2 * v2 );
    return { fx * ( u + du ) + cx, fy * ( v + dv ) + cy };
  }

  //! A small model in an arbitrary frame: cameras of several models, three images looking down at points.
  ColmapModel sampleModel()
  {
    ColmapModel m;
    m.cameras.push_back( { 1, "OPENCV", 1200, 900, { 1010.5, 1012.25, 601.3, 449.8, -0.08, 0.012, 0.0004, -0.0003 } } );
    m.cameras.push_back( { 2, "SIMPLE_RADIAL", 800, 600, { 700.0, 399.5, 300.25, -0.05 } } );
    m.cameras.push_back( { 3, "FULL_OPENCV", 640, 480, { 500, 501, 320, 240, -0.1, 0.02, 0.001, 0.0005, -0.003, 0, 0, 0 } } );
    std::mt19937 rng( 7 );
    std::uniform_real_distribution<double> angle( -0.15, 0.15 );
    for ( std::uint32_t i = 0; i < 4; ++i )
    {
      ColmapImage im;
      im.id = 10 + i;
      im.cameraId = 1 + i % 3;
      im.name = "frames/img_" + std::to_string( 100 + i ) + ".jpg";
      // looking down (+z of COLMAP's camera towards -z of the model frame), moving along x
      const Eigen::Matrix3d camFromWorld = ( Eigen::AngleAxisd( kPi + angle( rng ), Eigen::Vector3d::UnitX() ) * Eigen::AngleAxisd( angle( rng ), Eigen::Vector3d::UnitY() )
                                             * Eigen::AngleAxisd( angle( rng ) * 3, Eigen::Vector3d::UnitZ() ) ).toRotationMatrix();
      const Eigen::Vector3d centre( 2.0 * i, 0.3 * i * i, 10.0 + 0.2 * ( i % 2 ) );
      const Eigen::Quaterniond q( camFromWorld );
      im.qvec = { q.w(), q.x(), q.y(), q.z() };
      im.tvec = -camFromWorld * centre;
      m.images.push_back( im );
    }
    std::uniform_real_distribution<double> coord( -3.0, 9.0 );
    for ( std::uint64_t k = 0; k < 40; ++k )
    {
      ColmapPoint3D p;
      p.id = 1000 + k;
      p.xyz = { coord( rng ), coord( rng ) * 0.5, coord( rng ) * 0.1 };
      p.rgb = { 10, 20, static_cast<std::uint8_t>( k ) };
      p.error = 0.25;
      for ( ColmapImage &im : m.images )
      {
        const Eigen::Vector2d px = colmapProject( *m.findCamera( im.cameraId ), im, p.xyz );
        ColmapPoint2D p2;
        p2.pixel = px;
        p2.point3DId = static_cast<std::int64_t>( p.id );
        p.track.push_back( { im.id, static_cast<std::uint32_t>( im.points2D.size() ) } );
        im.points2D.push_back( p2 );
      }
      m.points3D.push_back( p );
    }
    // a 2-D point without a 3-D point
    m.images[0].points2D.push_back( { Eigen::Vector2d( 5.5, 6.5 ), -1 } );
    return m;
  }

  void expectSameModel( const ColmapModel &a, const ColmapModel &b )
  {
    ASSERT_EQ( a.cameras.size(), b.cameras.size() );
    for ( size_t i = 0; i < a.cameras.size(); ++i )
    {
      EXPECT_EQ( a.cameras[i].id, b.cameras[i].id );
      EXPECT_EQ( a.cameras[i].model, b.cameras[i].model );
      EXPECT_EQ( a.cameras[i].width, b.cameras[i].width );
      EXPECT_EQ( a.cameras[i].params, b.cameras[i].params );
    }
    ASSERT_EQ( a.images.size(), b.images.size() );
    for ( size_t i = 0; i < a.images.size(); ++i )
    {
      EXPECT_EQ( a.images[i].name, b.images[i].name );
      EXPECT_EQ( a.images[i].qvec, b.images[i].qvec );
      EXPECT_EQ( a.images[i].tvec, b.images[i].tvec );
      ASSERT_EQ( a.images[i].points2D.size(), b.images[i].points2D.size() );
      for ( size_t k = 0; k < a.images[i].points2D.size(); ++k )
      {
        EXPECT_EQ( a.images[i].points2D[k].pixel, b.images[i].points2D[k].pixel );
        EXPECT_EQ( a.images[i].points2D[k].point3DId, b.images[i].points2D[k].point3DId );
      }
    }
    ASSERT_EQ( a.points3D.size(), b.points3D.size() );
    for ( size_t i = 0; i < a.points3D.size(); ++i )
    {
      EXPECT_EQ( a.points3D[i].xyz, b.points3D[i].xyz );
      EXPECT_EQ( a.points3D[i].rgb, b.points3D[i].rgb );
      ASSERT_EQ( a.points3D[i].track.size(), b.points3D[i].track.size() );
      EXPECT_EQ( a.points3D[i].track.back().point2DIndex, b.points3D[i].track.back().point2DIndex );
    }
  }

  ColmapImportOptions noFiles()
  {
    ColmapImportOptions o;
    o.crs = kCrs;
    o.requireImageFiles = false;
    return o;
  }
} // namespace

TEST( ColmapModel, TextAndBinaryRoundTripExactly )
{
  const ColmapModel model = sampleModel();
  const fs::path dir = freshTestFolder( "colmap-roundtrip" );
  model.writeText( dir / "text" );
  model.writeBinary( dir / "bin" );
  expectSameModel( model, ColmapModel::read( dir / "text" ) );
  expectSameModel( model, ColmapModel::read( dir / "bin" / "images.bin" ) ); // a file of the model names its folder
  EXPECT_TRUE( ColmapModel::isModel( dir / "bin" ) );
  EXPECT_FALSE( ColmapModel::isModel( dir ) );
  fs::remove_all( dir );
}

TEST( ColmapConversion, ImportedBlockProjectsLikeColmap )
{
  // every supported camera model: GeoStation's projection through the
  // imported block equals COLMAP's own equations
  const ColmapModel model = sampleModel();
  const BlockImportSummary import = importColmapModel( model, [&] {
    const fs::path dir = freshTestFolder( "colmap-projection" );
    model.writeBinary( dir );
    return dir;
  }(), noFiles() );
  ASSERT_EQ( import.block.images.size(), 4u );
  double worst = 0.0;
  int compared = 0;
  for ( const ColmapImage &im : model.images )
  {
    const BlockImage &image = import.block.image( import.imageIdBySourceName.at( im.name ) );
    const OrientedImage oriented( import.block.cameraOf( image ), *image.exterior );
    for ( const ColmapPoint3D &p : model.points3D )
    {
      const GroundProjection g = oriented.projectGroundToPixel( p.xyz );
      ASSERT_TRUE( g.ok() );
      worst = std::max( worst, ( g.pixelInImage - colmapProject( *model.findCamera( im.cameraId ), im, p.xyz ) ).norm() );
      ++compared;
    }
  }
  EXPECT_EQ( compared, 160 );
  EXPECT_LT( worst, 1e-9 );
  // the observations carried over unchanged: projecting the tie points reproduces them
  ASSERT_EQ( import.tiePoints.size(), 40u );
  ASSERT_EQ( import.observations.size(), 160u );
  EXPECT_EQ( import.format, "colmap-binary" );
  EXPECT_EQ( import.block.stations.size(), 4u );
  EXPECT_EQ( import.block.images.front().id, "frames/img_100" );
  EXPECT_EQ( import.block.images.front().path, "frames/img_100.jpg" );
}

TEST( ColmapConversion, ACameraThatCannotBeCarriedSaysWhy )
{
  using Status = CameraConversionStatus;
  const ColmapCamera opencv { 3, "OPENCV", 4000, 3000, { 3000, 3010, 2000, 1500, -0.1, 0.01, 0.001, -0.002 } };
  const CameraFromColmap in = cameraFromColmap( opencv, "cam" );
  ASSERT_TRUE( in.ok() ) << in.message;
  EXPECT_EQ( in.camera.id, "cam" );
  EXPECT_EQ( in.camera.distortion.model, DistortionModel::OpenCV );
  const CameraToColmap back = colmapCameraFromCamera( in.camera, 7 );
  ASSERT_TRUE( back.ok() ) << back.message;
  EXPECT_EQ( back.camera.model, "OPENCV" );
  EXPECT_EQ( back.camera.id, 7u );
  for ( size_t i = 0; i < opencv.params.size(); ++i )
    EXPECT_NEAR( back.camera.params[i], opencv.params[i], 1e-9 * std::abs( opencv.params[i] ) + 1e-15 ) << i;

  const CameraFromColmap fisheye = cameraFromColmap( { 4, "OPENCV_FISHEYE", 4000, 3000, { 3000, 3000, 2000, 1500, 0.1, 0, 0, 0 } }, "cam" );
  EXPECT_EQ( fisheye.status, Status::NotRepresentable );
  EXPECT_NE( fisheye.message.find( "COLMAP camera 4 (OPENCV_FISHEYE)" ), std::string::npos ) << fisheye.message;
  const CameraFromColmap tooFew = cameraFromColmap( { 5, "PINHOLE", 4000, 3000, { 3000, 3000, 2000 } }, "cam" );
  EXPECT_EQ( tooFew.status, Status::Malformed );
  EXPECT_NE( tooFew.message.find( "parameters" ), std::string::npos ) << tooFew.message;
  const CameraFromColmap notANumber = cameraFromColmap( { 6, "SIMPLE_PINHOLE", 4000, 3000, { std::nan( "" ), 2000, 1500 } }, "cam" );
  EXPECT_EQ( notANumber.status, Status::Malformed );

  Camera brown = in.camera;
  brown.distortion.model = DistortionModel::BrownPhoto;
  const CameraToColmap refused = colmapCameraFromCamera( brown, 8 );
  EXPECT_EQ( refused.status, Status::NotRepresentable );
  EXPECT_NE( refused.message.find( "brown_photo" ), std::string::npos ) << refused.message;
}

TEST( ColmapConversion, PoseRoundTripAndAxes )
{
  // a COLMAP camera looking straight down with image right = +x: omega = phi = kappa = 0
  const ExteriorOrientation down = exteriorFromColmapPose( { 0, 1, 0, 0 }, { 0, 0, 10 } ); // 180 degrees about x
  EXPECT_NEAR( down.projectionCentre.z(), 10.0, 1e-12 );
  EXPECT_NEAR( std::abs( down.omegaDeg ), 0.0, 1e-9 );
  EXPECT_NEAR( down.phiDeg, 0.0, 1e-9 );
  EXPECT_NEAR( down.kappaDeg, 0.0, 1e-9 );
  std::mt19937 rng( 3 );
  std::uniform_real_distribution<double> a( -170, 170 ), b( -85, 85 );
  for ( int i = 0; i < 200; ++i )
  {
    ExteriorOrientation eo;
    eo.projectionCentre = { 500000.0 + a( rng ), 4400000.0 + a( rng ), 200.0 + b( rng ) };
    eo.omegaDeg = a( rng );
    eo.phiDeg = b( rng );
    eo.kappaDeg = a( rng );
    Eigen::Vector4d q;
    Eigen::Vector3d t;
    colmapPoseFromExterior( eo, &q, &t );
    EXPECT_GE( q[0], 0.0 );
    const ExteriorOrientation back = exteriorFromColmapPose( q, t );
    EXPECT_LE( ( back.projectionCentre - eo.projectionCentre ).cwiseAbs().maxCoeff(), 1e-9 );
    EXPECT_LT( ( back.worldFromCamera() - eo.worldFromCamera() ).cwiseAbs().maxCoeff(), 1e-14 );
  }
  EXPECT_NE( errorOf( [] { exteriorFromColmapPose( { 0, 0, 0, 0 }, { 0, 0, 0 } ); } ).find( "quaternion" ), std::string::npos );
}

TEST( ColmapImport, UnrepresentableCamerasAreDroppedByNameAndReported )
{
  ColmapModel model = sampleModel();
  model.cameras[1].model = "OPENCV_FISHEYE"; // 8 parameters, camera 2
  model.cameras[1].params = { 700, 700, 400, 300, 0.1, 0, 0, 0 };
  model.cameras[2].params[9] = 0.01; // FULL_OPENCV with a rational term, camera 3
  // point 1000 is seen only by images 11 and 12, whose cameras go
  std::vector<ColmapTrackElement> &track = model.points3D[0].track;
  track.erase( std::remove_if( track.begin(), track.end(), []( const ColmapTrackElement &t ) { return t.imageId == 10 || t.imageId == 13; } ), track.end() );
  const fs::path dir = freshTestFolder( "colmap-dropped" );
  model.writeText( dir );
  const BlockImportSummary import = importColmapModel( ColmapModel::read( dir ), dir, noFiles() );
  EXPECT_EQ( import.block.cameras.size(), 1u );
  EXPECT_EQ( import.block.images.size(), 2u ); // images 10 and 13 use camera 1
  ASSERT_GE( import.dropped.size(), 3u );
  EXPECT_NE( import.dropped[0].find( "OPENCV_FISHEYE" ), std::string::npos ) << import.dropped[0];
  EXPECT_NE( import.dropped[1].find( "k4, k5, k6" ), std::string::npos ) << import.dropped[1];
  EXPECT_NE( import.dropped.back().find( "fewer than two" ), std::string::npos );
  EXPECT_EQ( import.tiePoints.size(), 39u ); // the others are still seen by the two images left
  EXPECT_EQ( import.observations.size(), 78u );
  // nothing representable at all: one sentence, no block
  for ( ColmapCamera &c : model.cameras )
  {
    c.model = "FOV";
    c.params = { 1, 1, 1, 1, 0.1 };
  }
  EXPECT_NE( errorOf( [&] { importColmapModel( model, dir, noFiles() ); } ).find( "no image of the COLMAP model can be imported" ), std::string::npos );
  fs::remove_all( dir );
}

TEST( ColmapImport, GeoreferencedByCameraCentresOrControlPoints )
{
  // the model is the truth block seen through an arbitrary similarity;
  // georeferencing from the true centres brings it back exactly
  ColmapModel model = sampleModel();
  SimilarityTransform truthFromModel;
  truthFromModel.scale = 3.7;
  truthFromModel.rotation = ( Eigen::AngleAxisd( 0.7, Eigen::Vector3d( 0.2, -0.3, 1.0 ).normalized() ) ).toRotationMatrix();
  truthFromModel.translation = { 500123.4, 4400456.7, 212.3 };
  const fs::path dir = freshTestFolder( "colmap-georef" );
  model.writeText( dir );
  BlockImportSummary truthFrame = importColmapModel( model, dir, noFiles() );

  KnownPositions known;
  for ( const ColmapImage &im : model.images )
  {
    const BlockImage &image = truthFrame.block.image( truthFrame.imageIdBySourceName.at( im.name ) );
    known.cameraCentres[im.name] = truthFromModel.apply( image.exterior->projectionCentre );
  }
  known.cameraCentres["not/in/model.jpg"] = Eigen::Vector3d( 1, 2, 3 );
  BlockImportSummary byCameras = truthFrame;
  georeferenceImport( byCameras, known );
  ASSERT_TRUE( byCameras.georeference );
  EXPECT_NEAR( byCameras.georeference->targetFromSource.scale, 3.7, 1e-9 ); // target coordinates of 4.4e6 m over a 20 m block
  EXPECT_LT( byCameras.georeference->rmsM, 1e-8 );
  EXPECT_EQ( byCameras.georeference->residuals.size(), 4u );
  EXPECT_NE( byCameras.dropped.back().find( "not/in/model.jpg" ), std::string::npos );
  for ( size_t i = 0; i < byCameras.block.images.size(); ++i )
  {
    const ExteriorOrientation expected = truthFromModel.apply( *truthFrame.block.images[i].exterior );
    const ExteriorOrientation &got = *byCameras.block.images[i].exterior;
    EXPECT_LT( ( got.projectionCentre - expected.projectionCentre ).norm(), 1e-8 );
    EXPECT_LT( ( got.worldFromCamera() - expected.worldFromCamera() ).cwiseAbs().maxCoeff(), 1e-10 );
  }
  // the tie points moved with the cameras: they still project onto their observations
  const BlockImage &first = byCameras.block.images.front();
  const OrientedImage oriented( byCameras.block.cameraOf( first ), *first.exterior );
  for ( const ImportedObservation &o : byCameras.observations )
    if ( o.imageId == first.id )
    {
      const ImportedTiePoint &p = *std::find_if( byCameras.tiePoints.begin(), byCameras.tiePoints.end(), [&]( const ImportedTiePoint &t ) { return t.pointId == o.pointId; } );
      EXPECT_LT( ( oriented.projectGroundToPixel( p.world ).pixelInImage - o.pixelInImage ).norm(), 1e-6 );
    }

  // control points: tie point ids with true coordinates
  KnownPositions control;
  for ( int k : { 0, 7, 19, 33 } )
    control.controlPoints[truthFrame.tiePoints[k].pointId] = truthFromModel.apply( truthFrame.tiePoints[k].world );
  BlockImportSummary byControl = truthFrame;
  georeferenceImport( byControl, control );
  EXPECT_EQ( byControl.georeferenceFrom, "control points" );
  EXPECT_LT( ( byControl.block.images[2].exterior->projectionCentre - byCameras.block.images[2].exterior->projectionCentre ).norm(), 1e-7 );
  EXPECT_NE( importReportJsonText( byControl ).find( "\"rms_m\"" ), std::string::npos );

  // too few or collinear known positions: one sentence, the import unchanged
  KnownPositions two;
  two.cameraCentres = { *known.cameraCentres.begin(), *std::next( known.cameraCentres.begin() ) };
  BlockImportSummary untouched = truthFrame;
  EXPECT_NE( errorOf( [&] { georeferenceImport( untouched, two ); } ).find( "at least three camera centres" ), std::string::npos );
  EXPECT_EQ( untouched.block.images[0].exterior->projectionCentre, truthFrame.block.images[0].exterior->projectionCentre );
  EXPECT_NE( errorOf( [] { fitSimilarityTransform( { { 0, 0, 0 }, { 1, 1, 1 }, { 2, 2, 2 } }, { { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 } } ); } ).find( "on one line" ), std::string::npos );
  fs::remove_all( dir );
}

TEST( SimilarityTransform, NoisyFitReportsItsResiduals )
{
  std::mt19937 rng( 11 );
  std::normal_distribution<double> noise( 0.0, 0.02 );
  std::uniform_real_distribution<double> coord( -100, 100 );
  SimilarityTransform truth;
  truth.scale = 0.8;
  truth.rotation = Eigen::AngleAxisd( -1.1, Eigen::Vector3d::UnitZ() ).toRotationMatrix();
  truth.translation = { 400000, 5000000, 100 };
  std::vector<Eigen::Vector3d> source, target;
  for ( int i = 0; i < 200; ++i )
  {
    source.emplace_back( coord( rng ), coord( rng ), coord( rng ) * 0.2 );
    target.push_back( truth.apply( source.back() ) + Eigen::Vector3d( noise( rng ), noise( rng ), noise( rng ) ) );
  }
  const SimilarityFitSummary fit = fitSimilarityTransform( source, target );
  EXPECT_NEAR( fit.sigma0M, 0.02, 0.003 );
  EXPECT_NEAR( fit.targetFromSource.scale, 0.8, 1e-4 );
  const SimilarityTransform back = fit.targetFromSource.inverse();
  EXPECT_LT( ( back.apply( fit.targetFromSource.apply( source[5] ) ) - source[5] ).norm(), 1e-8 );
}

TEST( ColmapExport, BlockRoundTripsThroughColmapText )
{
  Block block;
  block.crs = kCrs;
  Camera left;
  left.id = "left";
  left.width = 1920;
  left.height = 1080;
  left.f = 1400.25;
  left.aspect = 1.0003;
  left.cx = 960.7;
  left.cy = 541.2;
  left.distortion.model = DistortionModel::OpenCV;
  left.distortion.coeffs = { -0.21, 0.05, 0.001, -0.0005, 0.002 };
  Camera plain = left;
  plain.id = "plain";
  plain.aspect = 1.0;
  plain.distortion = Distortion();
  Camera film = left;
  film.id = "film";
  film.pixelSizeMm = 0.01;
  film.distortion.model = DistortionModel::BrownPhoto;
  block.cameras = { left, plain, film };
  std::mt19937 rng( 5 );
  std::uniform_real_distribution<double> a( -179, 179 );
  for ( int i = 0; i < 6; ++i )
  {
    BlockImage image;
    image.id = "S" + std::to_string( 1000 + i ) + "_img";
    image.cameraId = i == 5 ? "film" : ( i % 2 ? "plain" : "left" );
    image.path = "images/" + image.id + ".tif";
    ExteriorOrientation eo;
    eo.projectionCentre = { 500123.456789 + 5 * i, 4400321.123456 + 0.3 * i, 212.4 };
    eo.omegaDeg = a( rng );
    eo.phiDeg = a( rng ) / 2.1;
    eo.kappaDeg = a( rng );
    if ( i != 4 )
      image.exterior = eo;
    block.images.push_back( image );
  }
  const fs::path dir = freshTestFolder( "colmap-export" );
  block.sourceFile = dir / "block.geostation.json";
  const BlockExportSummary written = exportBlockAsColmap( block, dir / "colmap" );
  EXPECT_EQ( written.images, 4 );
  ASSERT_EQ( written.dropped.size(), 2u );
  EXPECT_NE( written.dropped[0].find( "brown_photo" ), std::string::npos );
  EXPECT_NE( written.dropped[1].find( "not oriented" ), std::string::npos );
  EXPECT_FALSE( fs::exists( dir / "colmap" / ".geostation-export" ) );

  ColmapImportOptions options = noFiles();
  options.imageFolder = dir;
  const BlockImportSummary back = importColmapModel( ColmapModel::read( dir / "colmap" ), dir / "colmap", options );
  ASSERT_EQ( back.block.images.size(), 4u );
  double worstCentre = 0.0, worstAngle = 0.0;
  for ( const BlockImage &image : back.block.images )
  {
    const BlockImage &original = block.image( fs::path( image.path ).stem().string() );
    EXPECT_EQ( image.id, "images/" + original.id );
    const Camera &c0 = block.cameraOf( original ), &c1 = back.block.cameraOf( image );
    EXPECT_EQ( c1.f, c0.f );
    EXPECT_NEAR( c1.aspect, c0.aspect, 1e-15 );
    EXPECT_EQ( c1.cx, c0.cx );
    EXPECT_EQ( c1.cy, c0.cy );
    EXPECT_EQ( c1.distortion.model, c0.distortion.model );
    EXPECT_EQ( c1.distortion.coeffs, c0.distortion.coeffs );
    worstCentre = std::max( worstCentre, ( image.exterior->projectionCentre - original.exterior->projectionCentre ).cwiseAbs().maxCoeff() );
    worstAngle = std::max( worstAngle, ( image.exterior->worldFromCamera() - original.exterior->worldFromCamera() ).cwiseAbs().maxCoeff() );
    // and the saved block file keeps the paths of the original
  }
  EXPECT_LE( worstCentre, 1e-9 ); // metres per coordinate, at UTM coordinates of 4.4e6 m (one unit in the last place: 9.3e-10)
  std::cout << "round trip: largest coordinate difference " << worstCentre << " m, rotation element " << worstAngle << "\n";
  EXPECT_LT( worstAngle, 1e-14 );
  back.block.save( dir / "again.geostation.json" );
  EXPECT_EQ( Block::load( dir / "again.geostation.json" ).images.front().path, "images/S1000_img.tif" );

  exportBlockAsCsv( block, dir / "eo.csv" );
  std::ifstream csv( dir / "eo.csv" );
  std::string header, row;
  std::getline( csv, header );
  std::getline( csv, row );
  EXPECT_EQ( header.rfind( "image_id,camera,station,path,X,Y,Z,omega,phi,kappa", 0 ), 0u );
  EXPECT_EQ( row.rfind( "S1000_img,left,,images/S1000_img.tif,500123.456789", 0 ), 0u ) << row;
  fs::remove_all( dir );
}

TEST( ColmapImport, BadModelsAreRefusedWithOneSentence )
{
  const fs::path dir = freshTestFolder( "colmap-bad" );
  EXPECT_NE( errorOf( [&] { ColmapModel::read( dir / "nothing" ); } ).find( "does not exist" ), std::string::npos );
  EXPECT_NE( errorOf( [&] { ColmapModel::read( dir ); } ).find( "holds no COLMAP model" ), std::string::npos );

  const ColmapModel model = sampleModel();
  model.writeBinary( dir / "bin" );
  {
    // truncated images.bin
    const fs::path f = dir / "bin" / "images.bin";
    fs::resize_file( f, fs::file_size( f ) - 10 );
    const std::string e = errorOf( [&] { ColmapModel::read( dir / "bin" ); } );
    EXPECT_NE( e.find( "images.bin" ), std::string::npos ) << e;
    EXPECT_NE( e.find( "truncated" ), std::string::npos ) << e;
  }
  {
    // a count that does not fit the file
    std::ofstream( dir / "bin" / "cameras.bin", std::ios::binary ) << std::string( "\xff\xff\xff\xff\xff\xff\xff\x0f", 8 );
    const std::string e = errorOf( [&] { ColmapModel::read( dir / "bin" ); } );
    EXPECT_NE( e.find( "too short" ), std::string::npos ) << e;
  }
  model.writeText( dir / "txt" );
  {
    std::ofstream( dir / "txt" / "cameras.txt" ) << "# comment\n1 KANNALA 640 480 1 2 3\n";
    const std::string e = errorOf( [&] { ColmapModel::read( dir / "txt" ); } );
    EXPECT_NE( e.find( "cameras.txt, line 2: unknown camera model 'KANNALA'" ), std::string::npos ) << e;
    std::ofstream( dir / "txt" / "cameras.txt" ) << "1 PINHOLE 640 480 500 500 320\n";
    EXPECT_NE( errorOf( [&] { ColmapModel::read( dir / "txt" ); } ).find( "line 1: expected the 4 parameters of PINHOLE" ), std::string::npos );
  }
  {
    // the last image's empty line of 2-D points dropped by an editor: read as COLMAP reads it (no 2-D points)
    const fs::path folder = dir / "lastline";
    fs::create_directories( folder );
    std::ofstream( folder / "cameras.txt" ) << "1 PINHOLE 640 480 500 500 320 240\n";
    std::ofstream( folder / "images.txt" ) << "1 1 0 0 0 0 0 0 1 a.jpg\n10 20 -1\n2 1 0 0 0 1 0 0 1 b.jpg\n";
    const ColmapModel read = ColmapModel::read( folder );
    ASSERT_EQ( read.images.size(), 2u );
    EXPECT_EQ( read.images[0].points2D.size(), 1u );
    EXPECT_TRUE( read.images[1].points2D.empty() );
  }
  {
    // a track that names a 2-D point the image does not have
    ColmapModel broken = sampleModel();
    broken.points3D[3].track[1].point2DIndex = 999;
    EXPECT_NE( errorOf( [&] { importColmapModel( broken, dir / "bin", noFiles() ); } ).find( "inconsistent" ), std::string::npos );
  }
  {
    // images not on disk
    model.writeText( dir / "txt" );
    ColmapImportOptions options;
    options.crs = kCrs;
    const std::string e = errorOf( [&] { importColmapModel( model, dir / "txt", options ); } );
    EXPECT_NE( e.find( "the images of the COLMAP model were not found: \"frames/img_100.jpg\"" ), std::string::npos ) << e;
    options.crs = "EPSG:4326";
    EXPECT_NE( errorOf( [&] { importColmapModel( model, dir / "txt", options ); } ).find( "geographic" ), std::string::npos );
  }
  fs::remove_all( dir );
}
