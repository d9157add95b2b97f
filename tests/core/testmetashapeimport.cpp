// Metashape's camera XML, built exactly to the published format: the lens
// model checked against Metashape's projection equations, a referenced chunk
// (internal -> geocentric) brought into UTM against a truth pose computed with
// the east-north-up basis and the meridian convergence, and refusals.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <random>

#include <gtest/gtest.h>

#include "testfiles.h"
#include <opencv2/imgcodecs.hpp>

#include "geometry/crs.h"
#include "geometry/projection.h"
#include "geometry/rotation.h"
#include "io/metashapeimport.h"

using namespace geostation;
using geostation::testing::errorOf;
using geostation::testing::freshTestFolder;
namespace fs = std::filesystem;

namespace
{
  const int kWidth = 600, kHeight = 400;

  struct Calibration
  {
    double f = 510.0, cx = 3.25, cy = -2.5, b1 = 1.5, b2 = 0.0, k1 = -0.11, k2 = 0.02, k3 = 0.003, k4 = 0.0, p1 = 0.0004, p2 = -0.0002;
  };

  //! Metashape's frame camera projection (manual, "Camera models"): point in camera (x right, y down, z forward) to pixel.
  Eigen::Vector2d metashapeProject( const Calibration &c, const Eigen::Vector3d &p )
  {
    const double x = p.x() / p.z(), y = p.y() / p.z(), r2 = x * x + y * y;
    const double radial = 1 + c.k1 * r2 + c.k2 * r2 * r2 + c.k3 * r2 * r2 * r2 + c.k4 * r2 * r2 * r2 * r2;
    const double xd = x * radial + c.p1 * ( r2 + 2 * x * x ) + 2 * c.p2 * x * y;
    const double yd = y * radial + c.p2 * ( r2 + 2 * y * y ) + 2 * c.p1 * x * y;
    return { 0.5 * kWidth + c.cx + xd * c.f + xd * c.b1 + yd * c.b2, 0.5 * kHeight + c.cy + yd * c.f };
  }

  std::string sensorXml( int id, const Calibration &c, const std::string &type = "frame" )
  {
    std::ostringstream s;
    s << std::setprecision( 17 );
    s << "<sensor id=\"" << id << "\" label=\"cam" << id << "\" type=\"" << type << "\">\n<resolution width=\"" << kWidth << "\" height=\"" << kHeight << "\"/>\n"
      << "<calibration type=\"" << type << "\" class=\"adjusted\">\n<resolution width=\"" << kWidth << "\" height=\"" << kHeight << "\"/>\n"
      << "<f>" << c.f << "</f><cx>" << c.cx << "</cx><cy>" << c.cy << "</cy><b1>" << c.b1 << "</b1><b2>" << c.b2 << "</b2>"
      << "<k1>" << c.k1 << "</k1><k2>" << c.k2 << "</k2><k3>" << c.k3 << "</k3><k4>" << c.k4 << "</k4><p1>" << c.p1 << "</p1><p2>" << c.p2 << "</p2>\n"
      << "</calibration>\n</sensor>\n";
    return s.str();
  }

  std::string cameraXml( const std::string &label, int sensor, const Eigen::Matrix3d &rotation, const Eigen::Vector3d &centre )
  {
    std::ostringstream s;
    s << std::setprecision( 17 ) << "<camera id=\"" << label.size() << "\" sensor_id=\"" << sensor << "\" label=\"" << label << "\"><transform>";
    for ( int r = 0; r < 3; ++r )
      s << rotation( r, 0 ) << ' ' << rotation( r, 1 ) << ' ' << rotation( r, 2 ) << ' ' << centre[r] << ' ';
    s << "0 0 0 1</transform></camera>\n";
    return s.str();
  }


  /**
   * A camera in UTM 17N, 80 km east of the central meridian, as a referenced Metashape chunk holds it:
   * its pose in an arbitrary internal frame, and the chunk's <transform> (internal -> geocentric:
   * geocentric = s R p + T) with the WGS 84 <reference>.
   */
  struct ReferencedScene
  {
    Eigen::Vector3d truthCentre { 580000.0, 4430000.0, 650.0 };
    Eigen::Matrix3d truthWorldFromCamera = worldFromCameraRotationDeg( 2.5, -1.75, 33.0 );
    double gamma = 0.0; //!< meridian convergence (rad): the grid azimuth of true north is -gamma
    double s = 2.5;
    Eigen::Matrix3d chunkRotation = Eigen::AngleAxisd( 1.1, Eigen::Vector3d( 1, -2, 0.5 ).normalized() ).toRotationMatrix();
    Eigen::Vector3d chunkTranslation;
    Eigen::Matrix3d internalFromCamera;
    Eigen::Vector3d internalCentre;

    ReferencedScene()
    {
      // the camera's geocentric pose: east-north-up at the point, turned by the meridian convergence
      CrsTransform toGeographic( "EPSG:32617", "EPSG:4326" ), toGrid( "EPSG:4326", "EPSG:32617" ), toGeocentric( "EPSG:32617", "EPSG:4978" );
      const Eigen::Vector3d geo = toGeographic.transform( truthCentre );
      const Eigen::Vector3d north = toGrid.transform( geo + Eigen::Vector3d( 0, 1e-4, 0 ) ) - toGrid.transform( geo - Eigen::Vector3d( 0, 1e-4, 0 ) );
      gamma = -std::atan2( north.x(), north.y() );
      const double lat = degToRad( geo.y() ), lon = degToRad( geo.x() );
      Eigen::Matrix3d enuFromGeocentric;
      enuFromGeocentric << -std::sin( lon ), std::cos( lon ), 0, -std::sin( lat ) * std::cos( lon ), -std::sin( lat ) * std::sin( lon ), std::cos( lat ),
                        std::cos( lat ) * std::cos( lon ), std::cos( lat ) * std::sin( lon ), std::sin( lat );
      const Eigen::Matrix3d gridFromEnu = Eigen::AngleAxisd( gamma, Eigen::Vector3d::UnitZ() ).toRotationMatrix();
      const Eigen::Matrix3d flip = Eigen::Vector3d( 1, -1, -1 ).asDiagonal();
      const Eigen::Matrix3d geocentricFromCamera = ( gridFromEnu * enuFromGeocentric ).transpose() * truthWorldFromCamera * flip; // Metashape camera frame
      const Eigen::Vector3d geocentricCentre = toGeocentric.transform( truthCentre );
      chunkTranslation = geocentricCentre + Eigen::Vector3d( 120.0, -45.0, 80.0 );
      internalCentre = chunkRotation.transpose() * ( geocentricCentre - chunkTranslation ) / s;
      internalFromCamera = chunkRotation.transpose() * geocentricFromCamera;
    }

    //! The chunk's <transform> and <reference>.
    std::string chunkXml() const
    {
      std::ostringstream chunk;
      chunk << std::setprecision( 17 ) << "<transform><rotation>";
      for ( int r = 0; r < 3; ++r )
        chunk << chunkRotation( r, 0 ) << ' ' << chunkRotation( r, 1 ) << ' ' << chunkRotation( r, 2 ) << ' ';
      chunk << "</rotation><translation>" << chunkTranslation.x() << ' ' << chunkTranslation.y() << ' ' << chunkTranslation.z() << "</translation><scale>" << s
            << "</scale></transform>\n<reference>GEOGCS[\"WGS 84\",DATUM[\"World Geodetic System 1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.01745329251994328]]</reference>\n";
      return chunk.str();
    }

    //! A point in UTM 17N (ellipsoidal height) in the camera's frame as Metashape has it (x right, y down, z forward).
    Eigen::Vector3d inCamera( const Eigen::Vector3d &utm ) const
    {
      CrsTransform toGeocentric( "EPSG:32617", "EPSG:4978" );
      const Eigen::Vector3d internal = chunkRotation.transpose() * ( toGeocentric.transform( utm ) - chunkTranslation ) / s;
      return internalFromCamera.transpose() * ( internal - internalCentre );
    }
  };
} // namespace

TEST( MetashapeImport, LensModelProjectsLikeMetashape )
{
  const fs::path dir = freshTestFolder( "metashape-lens" );
  const Calibration c;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd( 0.3, Eigen::Vector3d( 0.2, 1.0, -0.4 ).normalized() ).toRotationMatrix(); // chunkFromCamera
  const Eigen::Vector3d centre( 12.5, -3.25, 40.0 );
  std::ofstream( dir / "cameras.xml" ) << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<document version=\"1.5.0\">\n<chunk label=\"Chunk 1\" enabled=\"true\">\n<sensors next_id=\"1\">\n"
                                       << sensorXml( 0, c ) << "</sensors>\n<cameras next_id=\"2\">\n" << cameraXml( "DSC0001", 0, rotation, centre )
                                       << "<camera id=\"9\" sensor_id=\"0\" label=\"DSC0002\"/>\n</cameras>\n</chunk>\n</document>\n";
  cv::imwrite( ( dir / "DSC0001.JPG" ).string(), cv::Mat( kHeight, kWidth, CV_8UC1, cv::Scalar( 100 ) ) );
  MetashapeImportOptions options;
  options.crs = "EPSG:32617";
  EXPECT_TRUE( isMetashapeCameras( dir / "cameras.xml" ) );
  const BlockImportSummary import = importMetashapeCameras( dir / "cameras.xml", options );
  ASSERT_EQ( import.block.images.size(), 1u );
  EXPECT_EQ( import.block.images[0].path, "DSC0001.JPG" );
  EXPECT_NE( import.dropped.back().find( "1 camera(s) without a <transform>" ), std::string::npos );
  const OrientedImage oriented( import.block.cameras[0], *import.block.images[0].exterior );
  std::mt19937 rng( 2 );
  std::uniform_real_distribution<double> u( -0.5, 0.5 );
  double worst = 0.0;
  for ( int i = 0; i < 200; ++i )
  {
    const Eigen::Vector3d inCamera( u( rng ) * 20, u( rng ) * 14, 20.0 + 10 * u( rng ) ); // Metashape's camera frame
    const GroundProjection g = oriented.projectGroundToPixel( rotation * inCamera + centre );
    ASSERT_TRUE( g.ok() );
    worst = std::max( worst, ( g.pixelInImage - metashapeProject( c, inCamera ) ).norm() );
  }
  EXPECT_LT( worst, 1e-9 );
  fs::remove_all( dir );
}

TEST( MetashapeImport, ReferencedChunkLandsOnTheTruthInUtm )
{
  const ReferencedScene scene;
  const Eigen::Vector3d &truthCentre = scene.truthCentre;
  const Eigen::Matrix3d &truthWorldFromCamera = scene.truthWorldFromCamera;
  const Eigen::Matrix3d &internalFromCamera = scene.internalFromCamera;
  const Eigen::Vector3d &internalCentre = scene.internalCentre;
  const double gamma = scene.gamma;
  const fs::path dir = freshTestFolder( "metashape-referenced" );
  Calibration c;
  Calibration fisheye;
  Calibration k4 = c;
  k4.k4 = 1e-4;
  std::ofstream( dir / "cameras.xml" ) << "<?xml version=\"1.0\"?>\n<document version=\"1.5.0\"><chunk>\n<sensors>" << sensorXml( 0, c ) << sensorXml( 1, fisheye, "fisheye" ) << sensorXml( 2, k4 )
                                       << "</sensors>\n<cameras>\n<group label=\"flight 1\">" << cameraXml( "IMG_7", 0, internalFromCamera, internalCentre ) << "</group>\n"
                                       << cameraXml( "IMG_8", 1, internalFromCamera, internalCentre ) << cameraXml( "IMG_9", 2, internalFromCamera, internalCentre )
                                       << "</cameras>\n" << scene.chunkXml() << "</chunk></document>\n";
  MetashapeImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  const BlockImportSummary import = importMetashapeCameras( dir / "cameras.xml", options );
  ASSERT_EQ( import.block.images.size(), 1u );
  ASSERT_EQ( import.dropped.size(), 2u );
  EXPECT_NE( import.dropped[0].find( "fisheye sensor" ), std::string::npos ) << import.dropped[0];
  EXPECT_NE( import.dropped[1].find( "uses k4" ), std::string::npos ) << import.dropped[1];
  const ExteriorOrientation &eo = *import.block.images[0].exterior;
  EXPECT_LT( ( eo.projectionCentre - truthCentre ).norm(), 1e-6 );
  EXPECT_LT( ( eo.worldFromCamera() - truthWorldFromCamera ).cwiseAbs().maxCoeff(), 1e-9 );
  EXPECT_GT( std::abs( radToDeg( gamma ) ), 0.5 ); // the convergence mattered
  std::cout << "referenced chunk: centre within " << ( eo.projectionCentre - truthCentre ).norm() << " m, rotation within "
            << ( eo.worldFromCamera() - truthWorldFromCamera ).cwiseAbs().maxCoeff() << " (convergence " << radToDeg( gamma ) << " deg)\n";

  // the image must be there when asked for
  options.requireImageFiles = true;
  EXPECT_NE( errorOf( [&] { importMetashapeCameras( dir / "cameras.xml", options ); } ).find( "the image of camera \"IMG_7\" is not in" ), std::string::npos );
  std::ofstream( dir / "broken.xml" ) << "<document><chunk><sensors>";
  EXPECT_NE( errorOf( [&] { importMetashapeCameras( dir / "broken.xml", options ); } ).find( "not well-formed XML" ), std::string::npos );
  EXPECT_FALSE( isMetashapeCameras( dir / "broken.xml" ) );
  fs::remove_all( dir );
}

TEST( MetashapeImport, MarkersBecomeControlAndCheckPointsMeasuredWherePinned )
{
  // four markers on the ground 30-60 m in front of the referenced camera; their references in WGS 84
  // (longitude, latitude, ellipsoidal height), their projections computed with Metashape's camera model
  const ReferencedScene scene;
  const Calibration c;
  const Eigen::Vector3d viewing = scene.truthWorldFromCamera * Eigen::Vector3d( 0, 0, -1 );
  const std::vector<Eigen::Vector3d> truth = { scene.truthCentre + 40.0 * viewing + Eigen::Vector3d( 3, 0, 0 ), scene.truthCentre + 55.0 * viewing + Eigen::Vector3d( -4, 2, 0 ),
                                               scene.truthCentre + 30.0 * viewing + Eigen::Vector3d( 1, -3, 0 ), scene.truthCentre + 60.0 * viewing };
  CrsTransform toGeographic( "EPSG:32617", "EPSG:4326" );
  std::ostringstream markers, locations;
  markers << std::setprecision( 17 ) << "<markers>\n";
  locations << std::setprecision( 17 ) << "<frames><frame id=\"0\"><markers>\n";
  for ( size_t i = 0; i < truth.size(); ++i )
  {
    const Eigen::Vector3d geo = toGeographic.transform( truth[i] );
    const Eigen::Vector2d px = metashapeProject( c, scene.inCamera( truth[i] ) );
    ASSERT_TRUE( px.x() > 0 && px.y() > 0 && px.x() < kWidth && px.y() < kHeight ) << i;
    markers << "<marker id=\"" << i << "\" label=\"GCP" << i + 1 << "\">";
    if ( i == 3 ) // no reference coordinates: a tie marker, not control
      markers << "</marker>\n";
    else
      markers << "<reference x=\"" << geo.x() << "\" y=\"" << geo.y() << "\" z=\"" << geo.z() << "\"" << ( i == 0 ? " sx=\"0.02\" sy=\"0.02\" sz=\"0.05\"" : "" )
              << " enabled=\"" << ( i == 1 ? "false" : "true" ) << "\"/></marker>\n";
    // measured in the camera (id 5); marker 2 only where Metashape projected it itself (not pinned); and in a camera that is not imported
    locations << "<marker marker_id=\"" << i << "\"><location camera_id=\"5\" pinned=\"" << ( i == 2 ? "false" : "true" ) << "\" x=\"" << px.x() << "\" y=\"" << px.y()
              << "\"/><location camera_id=\"77\" pinned=\"true\" x=\"10\" y=\"10\"/></marker>\n";
  }
  markers << "</markers>\n";
  locations << "</markers></frame></frames>\n";

  const fs::path dir = freshTestFolder( "metashape-markers" );
  std::ostringstream camera;
  camera << std::setprecision( 17 ) << "<camera id=\"5\" sensor_id=\"0\" label=\"IMG_7\"><transform>";
  for ( int r = 0; r < 3; ++r )
    camera << scene.internalFromCamera( r, 0 ) << ' ' << scene.internalFromCamera( r, 1 ) << ' ' << scene.internalFromCamera( r, 2 ) << ' ' << scene.internalCentre[r] << ' ';
  camera << "0 0 0 1</transform></camera>\n";
  std::ofstream( dir / "cameras.xml" ) << "<?xml version=\"1.0\"?>\n<document version=\"1.5.0\"><chunk>\n<sensors>" << sensorXml( 0, c ) << "</sensors>\n<cameras>\n"
                                       << camera.str() << "</cameras>\n" << markers.str() << scene.chunkXml() << locations.str() << "</chunk></document>\n";
  MetashapeImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  const BlockImportSummary import = importMetashapeCameras( dir / "cameras.xml", options );

  // three markers with references: GCP1 and GCP3 control, GCP2 (reference not enabled) a check point; GCP4 has none
  ASSERT_EQ( import.controlPoints.size(), 3u );
  const ImportedControlPoint &gcp1 = import.controlPoints[0], &gcp2 = import.controlPoints[1], &gcp3 = import.controlPoints[2];
  EXPECT_EQ( gcp1.pointId, "GCP1" );
  EXPECT_FALSE( gcp1.check );
  EXPECT_TRUE( gcp2.check );
  EXPECT_FALSE( gcp3.check );
  ASSERT_TRUE( gcp1.sigmaM.has_value() );
  EXPECT_EQ( *gcp1.sigmaM, Eigen::Vector3d( 0.02, 0.02, 0.05 ) );
  EXPECT_FALSE( gcp2.sigmaM.has_value() );
  for ( size_t i = 0; i < 3; ++i )
    EXPECT_LT( ( import.controlPoints[i].world - truth[i] ).norm(), 1e-6 ) << i;

  // observations: the pinned ones in the imported camera; each lands where the imported block projects its
  // point - to 0.1 px, not exactly: UTM scales plan distances by k = 0.9997 here and heights by 1, so in a
  // Cartesian camera model a point 40 m below and 50 m away is seen turned by up to 1.6e-4 rad (0.08 px)
  ASSERT_EQ( import.observations.size(), 2u );
  const OrientedImage oriented( import.block.cameras[0], *import.block.images[0].exterior );
  for ( const ImportedObservation &o : import.observations )
  {
    EXPECT_EQ( o.imageId, "IMG_7" );
    const ImportedControlPoint &p = o.pointId == "GCP1" ? gcp1 : gcp2;
    ASSERT_TRUE( o.pointId == "GCP1" || o.pointId == "GCP2" ) << o.pointId;
    const GroundProjection g = oriented.projectGroundToPixel( p.world );
    ASSERT_TRUE( g.ok() );
    EXPECT_LT( ( g.pixelInImage - o.pixelInImage ).norm(), 0.1 ) << o.pointId;
  }
  const auto said = []( const std::vector<std::string> &sentences, const std::string &part ) {
    return std::any_of( sentences.begin(), sentences.end(), [&]( const std::string &s ) { return s.find( part ) != std::string::npos; } );
  };
  EXPECT_TRUE( said( import.converted, "2 marker(s) became control points and 1 (reference not enabled) check points, their references brought into EPSG:32617" ) );
  EXPECT_TRUE( said( import.dropped, "1 marker(s) without reference coordinates were left out" ) );
  EXPECT_TRUE( said( import.dropped, "1 marker projection(s) not pinned" ) );
  EXPECT_TRUE( said( import.warnings, "1 marker(s) are measured in no imported image" ) );

  // the table bundle_adjust's GCPS reads
  writeControlTable( import, dir / "control.csv" );
  std::ifstream in( dir / "control.csv" );
  std::string header, first, second;
  std::getline( in, header );
  std::getline( in, first );
  std::getline( in, second );
  EXPECT_EQ( header, "point_id,X,Y,Z,sx,sy,sz,role" );
  const auto fields = []( const std::string &line ) {
    std::vector<std::string> out( 1 );
    for ( char ch : line )
    {
      if ( ch == ',' )
        out.emplace_back();
      else
        out.back().push_back( ch );
    }
    return out;
  };
  const std::vector<std::string> a = fields( first ), b = fields( second );
  ASSERT_EQ( a.size(), 8u );
  ASSERT_EQ( b.size(), 8u );
  EXPECT_EQ( a[0], "GCP1" );
  EXPECT_NEAR( std::stod( a[1] ), truth[0].x(), 1e-6 );
  EXPECT_NEAR( std::stod( a[6] ), 0.05, 1e-12 );
  EXPECT_EQ( a[7], "control" );
  EXPECT_EQ( b[4] + b[5] + b[6], "" ); // no accuracy given: fixed in bundle_adjust
  EXPECT_EQ( b[7], "check" );
  fs::remove_all( dir );
}
