/***************************************************************************
  innerorientationalgorithm.cpp - geostation:inner_orientation
 ***************************************************************************/
#include "innerorientationalgorithm.h"

#include <QJsonArray>
#include <QJsonObject>

#include <opencv2/imgcodecs.hpp>

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include "adjustment/innerorientation.h"
#include "imageproc/fiducialdetection.h"
#include "orientationreports.h"
#include "processingblock.h"
#include "processingtables.h"

namespace GeoStationProcessing
{

namespace
{
  const char *kCornerNames[4] = { "top_left", "top_right", "bottom_right", "bottom_left" };
}

QString InnerOrientationAlgorithm::name() const
{
  return QStringLiteral( "inner_orientation" );
}

QString InnerOrientationAlgorithm::displayName() const
{
  return QObject::tr( "Inner orientation from fiducials" );
}

QStringList InnerOrientationAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,inner orientation,fiducial,scan,film,affine,monoplotting" ).split( ',' );
}

QString InnerOrientationAlgorithm::group() const
{
  return QObject::tr( "Adjustment" );
}

QString InnerOrientationAlgorithm::groupId() const
{
  return QStringLiteral( "adjustment" );
}

QString InnerOrientationAlgorithm::helpText() const
{
  return QObject::tr( "Relates a scanned film photo's pixels to the camera's photo coordinates (mm) by an affine "
                      "transformation estimated from three or more fiducial marks, whose calibrated positions the "
                      "camera defines in the block (fiducials: id, x_mm, y_mm).\n\n"
                      "Measured marks come from FIDUCIALS (fiducial_id, col, row; rows of other images are ignored "
                      "when the table has image_id), or, with AUTO or without FIDUCIALS, are found automatically: one mark in each corner "
                      "window, matched on a subsampled copy against TEMPLATE (or a generic disc of MARK_DIAMETER_PX) "
                      "and refined by a centre of gravity at full resolution.\n\n"
                      "REPORT gives the scale factors A and B (mm per pixel) with their directions alpha_A and "
                      "alpha_B, the affinity in per cent (100 (A/B - 1)), the rotation beta, the fiducial residuals "
                      "and sigma0; REPORT_HTML the same for reading, with the residual vectors at the fiducials. "
                      "OUTPUT_BLOCK stores the affine with the image (inner_orientation)." );
}

InnerOrientationAlgorithm *InnerOrientationAlgorithm::createInstance() const
{
  return new InnerOrientationAlgorithm();
}

void InnerOrientationAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "IMAGE" ), QObject::tr( "Image id" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "FIDUCIALS" ), QObject::tr( "Measured fiducials (fiducial_id, col, row)" ),
                QList<int>() << QgsProcessing::TypeVector, QVariant(), true ) );
  addParameter( new QgsProcessingParameterBoolean( QStringLiteral( "AUTO" ), QObject::tr( "Find the fiducials automatically" ), false ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "TEMPLATE" ), QObject::tr( "Fiducial mark template (full resolution)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MARK_DIAMETER_PX" ), QObject::tr( "Generic mark: disc diameter (pixels)" ), QgsProcessingParameterNumber::Double, 30.0, false, 3.0 ) );
  addParameter( new QgsProcessingParameterBoolean( QStringLiteral( "DARK_MARK" ), QObject::tr( "Generic mark is dark on a bright background" ), false ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SCAN_PIXEL_MM" ), QObject::tr( "Scan pixel size (mm; default: the camera's)" ), QgsProcessingParameterNumber::Double, QVariant(), true, 1e-5 ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT_BLOCK" ), QObject::tr( "Block with inner orientation" ), QObject::tr( "GeoStation block (*.geostation.json)" ) ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
  addParameter( GeoStationProcessing::htmlReportParameter() );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "SIGMA0_MM" ), QObject::tr( "sigma0 (mm)" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "AFFINITY_PCT" ), QObject::tr( "Affinity (%)" ) ) );
}

QVariantMap InnerOrientationAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QString imageId = parameterAsString( parameters, QStringLiteral( "IMAGE" ), context ).trimmed();
  const geostation::BlockImage &image = GeoStationProcessing::blockImage( block, imageId );
  const geostation::Camera &camera = block.cameraOf( image );
  if ( camera.fiducials.size() < 3 )
    throw QgsProcessingException( QObject::tr( "Camera \"%1\" defines %2 fiducials; an inner orientation needs at least three (cameras[].fiducials in the block)." )
                                  .arg( QString::fromStdString( camera.id ) ).arg( camera.fiducials.size() ) );

  // without measured fiducials they are found automatically: what a user running it with the block and the image expects
  const bool automatic = parameterAsBool( parameters, QStringLiteral( "AUTO" ), context ) || !outputRequested( parameters, QStringLiteral( "FIDUCIALS" ) );
  std::vector<geostation::FiducialMeasurement> measured;
  QJsonArray detections;
  if ( automatic )
  {
    GeoStationProcessing::requireImageFile( block, image );
    geostation::FiducialDetectionOptions options;
    options.scanPixelMm = parameters.value( QStringLiteral( "SCAN_PIXEL_MM" ) ).isValid() && !parameters.value( QStringLiteral( "SCAN_PIXEL_MM" ) ).isNull()
                          ? parameterAsDouble( parameters, QStringLiteral( "SCAN_PIXEL_MM" ), context ) : camera.pixelSizeMm.value_or( 0.0 );
    if ( !( options.scanPixelMm > 0.0 ) )
      throw QgsProcessingException( QObject::tr( "Automatic detection needs the scan pixel size: set SCAN_PIXEL_MM or the camera's pixel_size_mm." ) );
    options.markDiameterPx = parameterAsDouble( parameters, QStringLiteral( "MARK_DIAMETER_PX" ), context );
    options.brightMark = !parameterAsBool( parameters, QStringLiteral( "DARK_MARK" ), context );
    if ( QgsRasterLayer *templateLayer = parameterAsRasterLayer( parameters, QStringLiteral( "TEMPLATE" ), context ) )
    {
      options.markTemplate = cv::imread( templateLayer->source().toStdString(), cv::IMREAD_GRAYSCALE );
      if ( options.markTemplate.empty() )
        throw QgsProcessingException( QObject::tr( "The template %1 cannot be read as a grey image." ).arg( templateLayer->source() ) );
    }
    std::array<geostation::DetectedFiducial, 4> found;
    found = geostation::detectCornerFiducials( block.imageFilePath( image ).string(), options );
    const std::array<std::string, 4> ids = geostation::cornerFiducialIds( camera.fiducials );
    for ( int k = 0; k < 4; ++k )
    {
      detections.append( QJsonObject { { "corner", kCornerNames[k] }, { "fiducial_id", QString::fromStdString( ids[k] ) }, { "found", found[k].found() },
        { "col", found[k].pixelInImage.x() }, { "row", found[k].pixelInImage.y() }, { "score", found[k].score }, { "reason", QString::fromStdString( found[k].message ) } } );
      if ( found[k].found() && !ids[k].empty() )
        measured.push_back( { ids[k], found[k].pixelInImage } );
      else
        feedback->pushWarning( QObject::tr( "No fiducial in the %1 corner: %2" ).arg( kCornerNames[k], found[k].found() ? QObject::tr( "the camera has no fiducial there" ) : QString::fromStdString( found[k].message ) ) );
    }
  }
  else
  {
    std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "FIDUCIALS" ), context ) );
    if ( !source )
      throw QgsProcessingException( QObject::tr( "The measured fiducials (FIDUCIALS) cannot be read." ) );
    for ( const GeoStationProcessing::FiducialRecord &r : GeoStationProcessing::readFiducials( source.get(), imageId ) )
      measured.push_back( { r.fiducialId.toStdString(), r.pixel } );
  }
  feedback->setProgress( 60 );

  geostation::InnerOrientationSummary s;
  s = geostation::innerOrientation( camera.fiducials, measured );
  if ( !s.ok() )
    throw QgsProcessingException( QObject::tr( "Inner orientation of %1 failed: %2" ).arg( imageId, QString::fromStdString( s.message ) ) );

  for ( geostation::BlockImage &i : block.images )
    if ( i.id == image.id )
      i.innerOrientation = geostation::ImageInnerOrientation { s.photoFromPixel, s.sigma0Mm };

  QJsonObject report { { "algorithm", "geostation:inner_orientation" }, { "image_id", imageId }, { "camera_id", QString::fromStdString( camera.id ) },
    { "method", automatic ? "auto" : "measured" }, { "A", s.decomposition.scaleA }, { "B", s.decomposition.scaleB },
    { "alpha_A", s.decomposition.alphaADeg }, { "alpha_B", s.decomposition.alphaBDeg }, { "affinity_pct", s.decomposition.affinityPct },
    { "beta", s.decomposition.betaDeg }, { "units", "A, B: mm per pixel; angles: degrees" },
    { "fiducial_centre_px", QJsonArray { s.fiducialCentrePx.x(), s.fiducialCentrePx.y() } },
    { "sigma0_mm", s.sigma0Mm }, { "redundancy", s.redundancy }, { "rms_residual_mm", s.rmsResidualMm } };
  QJsonArray residuals;
  for ( const geostation::FiducialResidual &r : s.residuals )
    residuals.append( QJsonObject { { "fiducial_id", QString::fromStdString( r.id ) }, { "dx_mm", r.residualMm.x() }, { "dy_mm", r.residualMm.y() } } );
  report.insert( "residuals", residuals );
  if ( automatic )
    report.insert( "detections", detections );

  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  const QString htmlPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT_HTML" ), context );
  const QString blockPath = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT_BLOCK" ), context );
  GeoStationProcessing::writeBlockAndReports( block, blockPath, { { reportPath, GeoStationProcessing::jsonReport( report ) },
    { htmlPath, htmlPath.isEmpty() ? QByteArray() : GeoStationProcessing::innerOrientationHtml( s, imageId, QString::fromStdString( camera.id ), measured ) } } );
  feedback->setProgress( 100 );
  feedback->pushInfo( QObject::tr( "%1: %2 fiducials, A = %3 mm/px, B = %4 mm/px, affinity %5 %, beta = %6 deg, sigma0 = %7 um." )
                      .arg( imageId ).arg( measured.size() ).arg( s.decomposition.scaleA, 0, 'f', 6 ).arg( s.decomposition.scaleB, 0, 'f', 6 )
                      .arg( s.decomposition.affinityPct, 0, 'f', 3 ).arg( s.decomposition.betaDeg, 0, 'f', 4 ).arg( s.sigma0Mm * 1000.0, 0, 'f', 2 ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT_BLOCK" ), blockPath );
  outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  outputs.insert( QStringLiteral( "REPORT_HTML" ), htmlPath );
  outputs.insert( QStringLiteral( "SIGMA0_MM" ), s.sigma0Mm );
  outputs.insert( QStringLiteral( "AFFINITY_PCT" ), s.decomposition.affinityPct );
  return outputs;
}

} // namespace GeoStationProcessing
