/***************************************************************************
  bundleadjustalgorithm.cpp - geostation:bundle_adjust
 ***************************************************************************/
#include "bundleadjustalgorithm.h"

#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsgeometry.h>
#include <qgspoint.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>

#include "adjustment/bundleadjustment.h"
#include "bundleadjustreport.h"
#include "orientationreports.h"
#include "processingblock.h"
#include "processingtables.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

QString BundleAdjustAlgorithm::name() const
{
  return QStringLiteral( "bundle_adjust" );
}

QString BundleAdjustAlgorithm::displayName() const
{
  return QObject::tr( "Bundle adjustment" );
}

QStringList BundleAdjustAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,bundle adjustment,triangulation,aerotriangulation,self-calibration,gnss,ins,tie points" ).split( ',' );
}

QString BundleAdjustAlgorithm::group() const
{
  return QObject::tr( "Adjustment" );
}

QString BundleAdjustAlgorithm::groupId() const
{
  return QStringLiteral( "adjustment" );
}

QString BundleAdjustAlgorithm::helpText() const
{
  return QObject::tr( "Adjusts the orientations of all observed images of a block together with every measured point.\n\n"
                      "OBSERVATIONS: point_id, image_id, col, row (pixels) and optionally sigma_px. GCPS (optional): point_id, X, Y, Z "
                      "(block CRS) or PointZ geometries, optionally sx, sy, sz (metres; 0 = fixed) and role (control or check). "
                      "Check points are adjusted like tie points and compared with their coordinates.\n\n"
                      "USE_POSE_PRIORS takes the images' GNSS/INS orientation with its sigmas as observations; without it, at "
                      "least three control points are needed. SELF_CALIBRATION lists interior parameters to estimate for every "
                      "camera (e.g. f,cx,cy,k1).\n\n"
                      "Every observed image needs a starting orientation (orient new images with Space resection first). "
                      "OUTPUT_BLOCK is the adjusted block with standard deviations; OUTPUT_POINTS a PointZ layer of all points "
                      "with point_id, role, n_images, sigma_x/y/z, rms_px and, for control and check points, err_x/y/z; REPORT "
                      "a JSON file with sigma0, per-image residuals and shifts, interior parameters, ground-point errors and "
                      "the RMSE on control and check points; REPORT_HTML the same for reading, with the largest residuals, "
                      "residual vectors over the images with the largest RMS and a histogram of all residuals." );
}

BundleAdjustAlgorithm *BundleAdjustAlgorithm::createInstance() const
{
  return new BundleAdjustAlgorithm();
}

void BundleAdjustAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "OBSERVATIONS" ), QObject::tr( "Image observations (point_id, image_id, col, row)" ), QList<int>() << QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "GCPS" ), QObject::tr( "Control and check points" ), QList<int>() << QgsProcessing::TypeVector, QVariant(), true ) );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "SELF_CALIBRATION" ), QObject::tr( "Interior parameters to estimate (e.g. f,cx,cy,k1)" ), QString(), false, true ) );
  addParameter( new QgsProcessingParameterBoolean( QStringLiteral( "USE_POSE_PRIORS" ), QObject::tr( "Use the GNSS/INS orientation sigmas as priors" ), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SIGMA_PX" ), QObject::tr( "Pixel sigma where the table has none" ), QgsProcessingParameterNumber::Double, 0.5, false, 1e-6 ) );
  addParameter( new QgsProcessingParameterBoolean( QStringLiteral( "ROBUST" ), QObject::tr( "Robust (Huber) loss while iterating" ), false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT_BLOCK" ), QObject::tr( "Adjusted block" ), QObject::tr( "GeoStation block (*.geostation.json)" ) ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT_POINTS" ), QObject::tr( "Adjusted points" ), QgsProcessing::TypeVectorPoint, QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
  addParameter( GeoStationProcessing::htmlReportParameter() );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "SIGMA0" ), QObject::tr( "sigma0 (px)" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "RMSE_CHECK_M" ), QObject::tr( "RMSE on check points (m, 3D)" ) ) );
}

QVariantMap BundleAdjustAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QgsCoordinateReferenceSystem crs = GeoStationProcessing::blockCrs( block );
  const double defaultSigma = parameterAsDouble( parameters, QStringLiteral( "SIGMA_PX" ), context );

  geostation::BundleOptions options;
  options.usePosePriors = parameterAsBool( parameters, QStringLiteral( "USE_POSE_PRIORS" ), context );
  options.robust = parameterAsBool( parameters, QStringLiteral( "ROBUST" ), context );
  for ( const QString &name : parameterAsString( parameters, QStringLiteral( "SELF_CALIBRATION" ), context ).split( ',', Qt::SkipEmptyParts ) )
  {
    const std::optional<int> index = geostation::interiorParameterIndex( name.trimmed().toStdString() );
    if ( !index )
      throw QgsProcessingException( QObject::tr( "SELF_CALIBRATION: \"%1\" is not an interior parameter; use any of f,cx,cy,k1,k2,p1,p2,k3." ).arg( name.trimmed() ) );
    options.freeInterior[*index] = true;
  }

  std::unique_ptr<QgsProcessingFeatureSource> observationSource( parameterAsSource( parameters, QStringLiteral( "OBSERVATIONS" ), context ) );
  if ( !observationSource )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "OBSERVATIONS" ) ) );
  const GeoStationProcessing::ObservationTable table = GeoStationProcessing::readObservations( observationSource.get(), QObject::tr( "observations" ), feedback );
  std::vector<geostation::ControlPoint> ground;
  std::unique_ptr<QgsProcessingFeatureSource> gcpSource( parameterAsSource( parameters, QStringLiteral( "GCPS" ), context ) );
  if ( gcpSource )
    for ( const GeoStationProcessing::GroundPointRecord &g : GeoStationProcessing::readGroundPoints( gcpSource.get(), QObject::tr( "control" ), crs, context.transformContext(), feedback ) )
      ground.push_back( { g.pointId.toStdString(), g.world, g.sigmaM, g.check } );

  // The observed images, each with its start orientation.
  std::vector<geostation::BundleImage> images;
  std::vector<geostation::BundleObservation> observations;
  QSet<QString> seen;
  for ( const GeoStationProcessing::ObservationRecord &r : table.rows )
  {
    if ( !seen.contains( r.imageId ) )
    {
      const geostation::BlockImage &image = GeoStationProcessing::blockImage( block, r.imageId );
      images.push_back( { image.id, image.cameraId, GeoStationProcessing::requireOriented( block, image ) } );
      seen.insert( r.imageId );
    }
    observations.push_back( { r.pointId.toStdString(), r.imageId.toStdString(), r.pixel, r.sigmaPx > 0.0 ? r.sigmaPx : defaultSigma } );
  }
  if ( observations.empty() )
    throw QgsProcessingException( QObject::tr( "The observations table is empty." ) );
  feedback->pushInfo( QObject::tr( "Adjusting %1 images, %2 observations, %3 ground points…" ).arg( images.size() ).arg( observations.size() ).arg( ground.size() ) );
  feedback->setProgress( 5 );

  // Cancel stops the solve between iterations; progress follows the iterations (5-75 %)
  options.progress = GeoStationProcessing::progressOf( feedback ).part( 0.05, 0.75 );
  geostation::BundleSummary summary;
  summary = geostation::bundleAdjust( block.cameras, images, ground, observations, options );
  if ( summary.status == geostation::BundleSummary::Status::Cancelled || feedback->isCanceled() )
    return QVariantMap(); // nothing written
  if ( !summary.ok() )
    throw QgsProcessingException( QObject::tr( "Bundle adjustment failed: %1" ).arg( QString::fromStdString( summary.message ) ) );
  feedback->setProgress( 80 );

  // The adjusted block.
  for ( const geostation::BundleImageResult &r : summary.images )
    for ( geostation::BlockImage &image : block.images )
      if ( image.id == r.id && r.observationCount > 0 )
        image.exterior = r.exterior;
  for ( const geostation::BundleCameraResult &c : summary.cameras )
    for ( geostation::Camera &camera : block.cameras )
      if ( camera.id == c.camera.id )
        camera = c.camera;

  // The points layer, prepared before any file is written.
  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kPointId ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kRole ), QVariant::String ) );
  fields.append( QgsField( QStringLiteral( "n_images" ), QVariant::Int ) );
  for ( const char *name : { "sigma_x", "sigma_y", "sigma_z", "rms_px", "err_x", "err_y", "err_z" } )
    fields.append( QgsField( QString::fromLatin1( name ), QVariant::Double ) );
  QVector<QgsFeature> features;
  for ( const geostation::BundlePointResult &p : summary.points )
  {
    QgsFeature f( fields );
    f.setGeometry( QgsGeometry( new QgsPoint( p.world.x(), p.world.y(), p.world.z() ) ) );
    const bool known = p.role != geostation::BundlePointResult::Role::Tie;
    f.setAttributes( QgsAttributes() << QString::fromStdString( p.id ) << GeoStationProcessing::bundlePointRoleName( p.role ) << p.imageCount << p.sigmaM.x() << p.sigmaM.y() << p.sigmaM.z() << p.rmsPx
                     << ( known ? QVariant( p.errorM.x() ) : QVariant() ) << ( known ? QVariant( p.errorM.y() ) : QVariant() ) << ( known ? QVariant( p.errorM.z() ) : QVariant() ) );
    features << f;
  }

  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  const QString htmlPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT_HTML" ), context );
  const QString blockPath = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT_BLOCK" ), context );
  GeoStationProcessing::writeBlockAndReports( block, blockPath, { { reportPath, GeoStationProcessing::jsonReport( GeoStationProcessing::bundleAdjustReport( summary ) ) },
                                                                  { htmlPath, htmlPath.isEmpty() ? QByteArray() : GeoStationProcessing::bundleAdjustHtml( summary, block ) } } );

  QString pointsDestination;
  if ( outputRequested( parameters, QStringLiteral( "OUTPUT_POINTS" ) ) )
  {
    OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT_POINTS" ), context, fields, QgsWkbTypes::PointZ, crs );
    for ( QgsFeature &f : features )
      sink.add( f );
    pointsDestination = sink.close();
  }
  feedback->setProgress( 100 );

  feedback->pushInfo( QObject::tr( "sigma0 = %1 px, residual RMS %2 px, %3 iterations, %4 s." ).arg( summary.sigma0, 0, 'f', 3 ).arg( summary.rmsPx, 0, 'f', 3 )
                      .arg( summary.iterations ).arg( summary.solveSeconds, 0, 'f', 2 ) );
  if ( summary.checkCount )
    feedback->pushInfo( QObject::tr( "Check points: %1, RMSE X %2 m, Y %3 m, Z %4 m." ).arg( summary.checkCount )
                        .arg( summary.rmseCheckM.x(), 0, 'f', 3 ).arg( summary.rmseCheckM.y(), 0, 'f', 3 ).arg( summary.rmseCheckM.z(), 0, 'f', 3 ) );
  if ( !summary.skippedPoints.empty() )
    feedback->pushWarning( QString::fromStdString( summary.message ) );

  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT_BLOCK" ), blockPath );
  outputs.insert( QStringLiteral( "OUTPUT_POINTS" ), pointsDestination );
  outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  outputs.insert( QStringLiteral( "REPORT_HTML" ), htmlPath );
  outputs.insert( QStringLiteral( "SIGMA0" ), summary.sigma0 );
  outputs.insert( QStringLiteral( "RMSE_CHECK_M" ), summary.checkCount ? QVariant( summary.rmseCheckM.norm() ) : QVariant() );
  return outputs;
}

} // namespace GeoStationProcessing
