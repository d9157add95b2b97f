// Metashape's camera XML, built exactly to the published format: the lens
// model checked against Metashape's projection equations, a referenced chunk
// (internal -> geocentric) brought into UTM against a truth pose computed with
// the east-north-up basis and the meridian convergence, and refusals.
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
  // the truth: a camera in UTM 17N, 80 km east of the central meridian
  const Eigen::Vector3d truthCentre( 580000.0, 4430000.0, 650.0 );
  const double omega = 2.5, phi = -1.75, kappa = 33.0;
  const Eigen::Matrix3d truthWorldFromCamera = worldFromCameraRotationDeg( omega, phi, kappa );

  // its geocentric pose: east-north-up at the point, turned by the meridian convergence
  CrsTransform toGeographic( "EPSG:32617", "EPSG:4326" ), toGrid( "EPSG:4326", "EPSG:32617" ), toGeocentric( "EPSG:32617", "EPSG:4978" );
  const Eigen::Vector3d geo = toGeographic.transform( truthCentre );
  const Eigen::Vector3d north = toGrid.transform( geo + Eigen::Vector3d( 0, 1e-4, 0 ) ) - toGrid.transform( geo - Eigen::Vector3d( 0, 1e-4, 0 ) );
  const double gamma = -std::atan2( north.x(), north.y() ); // grid azimuth of true north is -gamma
  const double lat = degToRad( geo.y() ), lon = degToRad( geo.x() );
  Eigen::Matrix3d enuFromGeocentric;
  enuFromGeocentric << -std::sin( lon ), std::cos( lon ), 0, -std::sin( lat ) * std::cos( lon ), -std::sin( lat ) * std::sin( lon ), std::cos( lat ),
                    std::cos( lat ) * std::cos( lon ), std::cos( lat ) * std::sin( lon ), std::sin( lat );
  const Eigen::Matrix3d gridFromEnu = Eigen::AngleAxisd( gamma, Eigen::Vector3d::UnitZ() ).toRotationMatrix();
  const Eigen::Matrix3d flip = Eigen::Vector3d( 1, -1, -1 ).asDiagonal();
  const Eigen::Matrix3d geocentricFromCamera = ( gridFromEnu * enuFromGeocentric ).transpose() * truthWorldFromCamera * flip; // Metashape camera frame
  const Eigen::Vector3d geocentricCentre = toGeocentric.transform( truthCentre );

  // an arbitrary internal frame: geocentric = s R p + T
  const double s = 2.5;
  const Eigen::Matrix3d chunkRotation = Eigen::AngleAxisd( 1.1, Eigen::Vector3d( 1, -2, 0.5 ).normalized() ).toRotationMatrix();
  const Eigen::Vector3d chunkTranslation = geocentricCentre + Eigen::Vector3d( 120.0, -45.0, 80.0 );
  const Eigen::Vector3d internalCentre = chunkRotation.transpose() * ( geocentricCentre - chunkTranslation ) / s;
  const Eigen::Matrix3d internalFromCamera = chunkRotation.transpose() * geocentricFromCamera;

  const fs::path dir = freshTestFolder( "metashape-referenced" );
  std::ostringstream chunk;
  chunk << std::setprecision( 17 ) << "<transform><rotation>";
  for ( int r = 0; r < 3; ++r )
    chunk << chunkRotation( r, 0 ) << ' ' << chunkRotation( r, 1 ) << ' ' << chunkRotation( r, 2 ) << ' ';
  chunk << "</rotation><translation>" << chunkTranslation.x() << ' ' << chunkTranslation.y() << ' ' << chunkTranslation.z() << "</translation><scale>" << s
        << "</scale></transform>\n<reference>GEOGCS[\"WGS 84\",DATUM[\"World Geodetic System 1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.01745329251994328]]</reference>\n";
  Calibration c;
  Calibration fisheye;
  Calibration k4 = c;
  k4.k4 = 1e-4;
  std::ofstream( dir / "cameras.xml" ) << "<?xml version=\"1.0\"?>\n<document version=\"1.5.0\"><chunk>\n<sensors>" << sensorXml( 0, c ) << sensorXml( 1, fisheye, "fisheye" ) << sensorXml( 2, k4 )
                                       << "</sensors>\n<cameras>\n<group label=\"flight 1\">" << cameraXml( "IMG_7", 0, internalFromCamera, internalCentre ) << "</group>\n"
                                       << cameraXml( "IMG_8", 1, internalFromCamera, internalCentre ) << cameraXml( "IMG_9", 2, internalFromCamera, internalCentre )
                                       << "</cameras>\n" << chunk.str() << "</chunk></document>\n";
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
