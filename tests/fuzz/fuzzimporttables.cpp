/***************************************************************************
  fuzzimporttables.cpp - the text formats of a mapping van and of Metashape
  -------------------------------------------------------------------------
  trajectory_csv: a trajectory table for a one-camera rig
  (importTrajectory(), image files not required).
  events_csv: an events table interpolated in a fixed 10 Hz trajectory.
  metashape_xml: Metashape's camera XML (importMetashapeCameras(), image
  files not required).
  opencv_calibration: an OpenCV calibration file, YAML (input starting with
  "%YAML" or anything but "<") or XML (readOpenCvCalibration()).

  Each either throws std::invalid_argument with a message or gives cameras
  and images that are complete: every image has its camera and a finite
  exterior orientation, every camera a positive size and finite focal
  length; Metashape's markers finite, observed in imported images.
 ***************************************************************************/
#include "fuzztarget.h"

#include <cmath>

#include "io/metashapeimport.h"
#include "io/opencvcalibration.h"
#include "io/trajectoryimport.h"
#include "rigcameras.h"

namespace
{
  namespace fuzz = geostation::fuzz;

  void requireFiniteCamera( const geostation::Camera &camera )
  {
    if ( camera.width <= 0 || camera.height <= 0 || !std::isfinite( camera.f ) || !std::isfinite( camera.cx ) || !std::isfinite( camera.cy ) )
      fuzz::violated( "camera \"" + camera.id + "\" without a positive size or a finite focal length and principal point" );
  }

  void requireCompleteBlock( const geostation::Block &block )
  {
    fuzz::outcome( "imported: " + std::to_string( block.cameras.size() ) + " cameras, " + std::to_string( block.images.size() ) + " images" );
    for ( const auto &camera : block.cameras )
      requireFiniteCamera( camera );
    for ( const auto &image : block.images )
    {
      if ( !block.findCamera( image.cameraId ) )
        fuzz::violated( "image \"" + image.id + "\" without its camera" );
      if ( image.exterior )
      {
        const auto &eo = *image.exterior;
        if ( !eo.projectionCentre.allFinite() || !std::isfinite( eo.omegaDeg ) || !std::isfinite( eo.phiDeg ) || !std::isfinite( eo.kappaDeg ) )
          fuzz::violated( "image \"" + image.id + "\" with an exterior orientation that is not finite" );
      }
    }
  }
}

GEOSTATION_FUZZ_TARGET( trajectory_csv )
{
  const std::filesystem::path folder = fuzz::scratchFolder( "trajectory_csv" );
  fuzz::writeBytes( folder / "trajectory.csv", data, size );
  geostation::RigCamera front = geostation::testing::forwardRigCamera( "img/{station}_front.png" );
  front.leverArmM = Eigen::Vector3d( 1.0, 0.0, -2.0 );
  geostation::TrajectoryImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  for ( const bool withPattern : { true, false } )
  {
    geostation::RigCamera camera = front;
    if ( !withPattern )
      camera.imagePattern.clear();
    try
    {
      requireCompleteBlock( geostation::importTrajectory( { camera }, folder / "trajectory.csv", options ).block );
    }
    catch ( const std::invalid_argument &error )
    {
      fuzz::requireMessage( error );
    }
  }
  return 0;
}

GEOSTATION_FUZZ_TARGET( events_csv )
{
  // the input is the events table; the trajectory is fixed: 10 Hz over one second, in UTC
  const std::filesystem::path folder = fuzz::scratchFolder( "events_csv" );
  fuzz::writeBytes( folder / "events.csv", data, size );
  {
    std::string trajectory = "time,X,Y,Z,roll,pitch,heading\n";
    for ( int i = 0; i <= 10; ++i )
      trajectory += "2026-05-04T10:00:0" + std::string( i == 10 ? "1.0" : "0." + std::to_string( i ) ) + "Z," + std::to_string( 560000 + i ) + ",4400000,200,0.5,-0.5," + std::to_string( 355 + i ) + "\n";
    fuzz::writeBytes( folder / "trajectory.csv", reinterpret_cast<const uint8_t *>( trajectory.data() ), trajectory.size() );
  }
  const geostation::RigCamera camera = geostation::testing::forwardRigCamera( "img/{station}_{time}.png" );
  geostation::TrajectoryImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  options.eventsCsv = folder / "events.csv";
  try
  {
    requireCompleteBlock( geostation::importTrajectory( { camera }, folder / "trajectory.csv", options ).block );
  }
  catch ( const std::invalid_argument &error )
  {
    fuzz::requireMessage( error );
  }
  return 0;
}

GEOSTATION_FUZZ_TARGET( metashape_xml )
{
  const std::filesystem::path folder = fuzz::scratchFolder( "metashape_xml" );
  fuzz::writeBytes( folder / "cameras.xml", data, size );
  geostation::MetashapeImportOptions options;
  options.crs = "EPSG:32617";
  options.requireImageFiles = false;
  geostation::isMetashapeCameras( folder / "cameras.xml" );
  try
  {
    const geostation::BlockImportSummary import = geostation::importMetashapeCameras( folder / "cameras.xml", options );
    requireCompleteBlock( import.block );
    fuzz::outcome( "markers: " + std::to_string( import.controlPoints.size() ) + " control and check points, " + std::to_string( import.observations.size() ) + " observations" );
    for ( const auto &point : import.controlPoints )
      if ( !point.world.allFinite() || ( point.sigmaM && !point.sigmaM->allFinite() ) )
        fuzz::violated( "marker \"" + point.pointId + "\" with a position or accuracy that is not finite" );
    for ( const auto &o : import.observations )
      if ( !import.block.findImage( o.imageId ) || !o.pixelInImage.allFinite() )
        fuzz::violated( "an observation of marker \"" + o.pointId + "\" not in an imported image, or not finite" );
  }
  catch ( const std::invalid_argument &error )
  {
    fuzz::requireMessage( error );
  }
  return 0;
}

GEOSTATION_FUZZ_TARGET( opencv_calibration )
{
  const std::filesystem::path folder = fuzz::scratchFolder( "opencv_calibration" );
  const bool xml = size > 0 && data[0] == '<';
  const std::filesystem::path file = folder / ( xml ? "rig.xml" : "rig.yaml" );
  fuzz::writeBytes( file, data, size );
  geostation::isOpenCvCalibration( file );
  try
  {
    const std::vector<geostation::RigCamera> cameras = geostation::readOpenCvCalibration( file );
    fuzz::outcome( "read: " + std::to_string( cameras.size() ) + " cameras" );
    for ( const auto &camera : cameras )
    {
      requireFiniteCamera( camera.camera );
      if ( !camera.leverArmM.allFinite() || !camera.boresightDeg.allFinite() )
        fuzz::violated( "rig camera \"" + camera.camera.id + "\" with a lever arm or boresight that is not finite" );
    }
  }
  catch ( const std::invalid_argument &error )
  {
    fuzz::requireMessage( error );
  }
  return 0;
}
