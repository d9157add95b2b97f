/***************************************************************************
  resectionalgorithm.cpp - geostation:resection
 ***************************************************************************/
#include "resectionalgorithm.h"

#include <QJsonArray>
#include <QJsonObject>

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>

#include "adjustment/resection.h"
#include "processingblock.h"
#include "orientationreports.h"
#include "processingtables.h"

namespace GeoStationProcessing
{

namespace
{
  const QString sAllInterior = QStringLiteral( "f,cx,cy,k1,k2,p1,p2,k3" );

  QJsonObject reportJson( const geostation::ResectionSummary &s, const QString &imageId, const QString &cameraId )
  {
    QJsonObject report;
    report.insert( QStringLiteral( "algorithm" ), QStringLiteral( "geostation:resection" ) );
    report.insert( QStringLiteral( "image_id" ), imageId );
    report.insert( QStringLiteral( "camera_id" ), cameraId );
    report.insert( QStringLiteral( "sigma0_px" ), s.sigma0 );
    report.insert( QStringLiteral( "redundancy" ), s.redundancy );
    report.insert( QStringLiteral( "iterations" ), s.iterations );
    report.insert( QStringLiteral( "converged" ), s.converged );
    QJsonArray parameters;
    for ( size_t i = 0; i < s.parameterNames.size(); ++i )
    {
      const QString name = QString::fromStdString( s.parameterNames[i] );
      const QString unit = i < 3 ? QStringLiteral( "m" ) : i < 6 ? QStringLiteral( "deg" ) : ( name == "f" || name == "cx" || name == "cy" ) ? QStringLiteral( "px" ) : QString();
      parameters.append( QJsonObject { { "name", name }, { "value", s.estimates[i] }, { "sigma", s.sigmas[i] }, { "unit", unit } } );
    }
    report.insert( QStringLiteral( "parameters" ), parameters );
    QJsonArray correlation;
    for ( int r = 0; r < s.correlation.rows(); ++r )
    {
      QJsonArray row;
      for ( int c = 0; c < s.correlation.cols(); ++c )
        row.append( s.correlation( r, c ) );
      correlation.append( row );
    }
    report.insert( QStringLiteral( "correlation" ), correlation );
    QJsonArray residuals;
    for ( const geostation::PointResidual &r : s.residuals )
    {
      QJsonObject o { { "point_id", QString::fromStdString( r.pointId ) },
        { "role", r.check ? "check" : "control" },
        { "col_resid_px", r.residualPx.x() }, { "row_resid_px", r.residualPx.y() },
        { "resid_px", r.residualPx.norm() },
        { "w", r.normalised }, { "blunder", r.blunder } };
      if ( r.check || r.blunder )
        o.insert( QStringLiteral( "ground_error_m" ), QJsonArray { r.groundErrorM.x(), r.groundErrorM.y() } );
      residuals.append( o );
    }
    report.insert( QStringLiteral( "residuals" ), residuals );
    report.insert( QStringLiteral( "rmse_control_px" ), s.rmseControlPx );
    report.insert( QStringLiteral( "rmse_check_px" ), s.checkCount ? QJsonValue( s.rmseCheckPx ) : QJsonValue() );
    report.insert( QStringLiteral( "rmse_check_m" ), s.checkCount ? QJsonValue( s.rmseCheckM ) : QJsonValue() );
    report.insert( QStringLiteral( "control_count" ), s.controlCount );
    report.insert( QStringLiteral( "check_count" ), s.checkCount );
    QJsonArray blunders;
    for ( const std::string &b : s.blunders )
      blunders.append( QString::fromStdString( b ) );
    report.insert( QStringLiteral( "blunders" ), blunders );
    report.insert( QStringLiteral( "message" ), QString::fromStdString( s.message ) );
    return report;
  }
} // namespace

QString ResectionAlgorithm::name() const
{
  return QStringLiteral( "resection" );
}

QString ResectionAlgorithm::displayName() const
{
  return QObject::tr( "Space resection of an image" );
}

QStringList ResectionAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,resection,exterior orientation,control points,gcp,pnp,calibration" ).split( ',' );
}

QString ResectionAlgorithm::group() const
{
  return QObject::tr( "Adjustment" );
}

QString ResectionAlgorithm::groupId() const
{
  return QStringLiteral( "adjustment" );
}

QString ResectionAlgorithm::helpText() const
{
  return QObject::tr( "Orients one image of a block from four or more control points measured in it. No approximate "
                      "orientation is needed. GCPS has point_id, X, Y, Z (block CRS; or PointZ geometries) and optionally "
                      "sx, sy, sz (metres; 0 = fixed) and role (control or check). OBSERVATIONS has point_id, image_id, col, "
                      "row and optionally sigma_px; rows of other images are ignored.\n\n"
                      "FIX lists the interior parameters held fixed (default all: f,cx,cy,k1,k2,p1,p2,k3); leave one out "
                      "to estimate it. When interior parameters are estimated, the image gets a camera of its own "
                      "(CAMERA@IMAGE) so the block's other images keep theirs.\n\n"
                      "A control point whose normalised residual exceeds BLUNDER_W is removed and the resection repeated; "
                      "it is named in the log and the report. OUTPUT_BLOCK is the block with the image oriented (with "
                      "standard deviations); REPORT is a JSON file with sigma0, the parameters with standard deviations, "
                      "their correlation matrix, per-point residuals and the RMSE on control and check points; REPORT_HTML the "
                      "same for reading, with the residual vectors drawn over the image and their histogram." );
}

ResectionAlgorithm *ResectionAlgorithm::createInstance() const
{
  return new ResectionAlgorithm();
}

void ResectionAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "IMAGE" ), QObject::tr( "Image id" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "GCPS" ), QObject::tr( "Ground control (point_id, X, Y, Z)" ), QList<int>() << QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "OBSERVATIONS" ), QObject::tr( "Image observations (point_id, image_id, col, row)" ), QList<int>() << QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "FIX" ), QObject::tr( "Interior parameters held fixed" ), sAllInterior, false, true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SIGMA_PX" ), QObject::tr( "Pixel sigma where the table has none" ), QgsProcessingParameterNumber::Double, 0.5, false, 1e-6 ) );
  addParameter( new QgsProcessingParameterBoolean( QStringLiteral( "ROBUST" ), QObject::tr( "Robust (Huber) loss while iterating" ), false ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "BLUNDER_W" ), QObject::tr( "Blunder threshold (normalised residual)" ), QgsProcessingParameterNumber::Double, 4.0, false, 1.0 ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "OUTPUT_BLOCK" ), QObject::tr( "Oriented block" ), QObject::tr( "GeoStation block (*.geostation.json)" ) ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
  addParameter( GeoStationProcessing::htmlReportParameter() );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "SIGMA0" ), QObject::tr( "sigma0 (px)" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "RMSE_CHECK_M" ), QObject::tr( "RMSE on check points (m)" ) ) );
  addOutput( new QgsProcessingOutputString( QStringLiteral( "BLUNDERS" ), QObject::tr( "Control points removed as blunders" ) ) );
}

QVariantMap ResectionAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QString imageId = parameterAsString( parameters, QStringLiteral( "IMAGE" ), context ).trimmed();
  const geostation::BlockImage &image = GeoStationProcessing::blockImage( block, imageId );
  const geostation::Camera &camera = block.cameraOf( image );
  const QgsCoordinateReferenceSystem crs = GeoStationProcessing::blockCrs( block );

  geostation::ResectionOptions options;
  options.freeInterior.fill( true );
  const QString fix = parameters.value( QStringLiteral( "FIX" ) ).isValid() ? parameterAsString( parameters, QStringLiteral( "FIX" ), context ) : sAllInterior;
  for ( const QString &name : fix.split( ',', Qt::SkipEmptyParts ) )
  {
    const std::optional<int> index = geostation::interiorParameterIndex( name.trimmed().toStdString() );
    if ( !index )
      throw QgsProcessingException( QObject::tr( "FIX: \"%1\" is not an interior parameter; use any of %2." ).arg( name.trimmed(), sAllInterior ) );
    options.freeInterior[*index] = false;
  }
  if ( camera.distortion.model == geostation::DistortionModel::None )
    for ( int k = geostation::kInteriorK1; k < geostation::kInteriorSize; ++k )
      options.freeInterior[k] = false; // a camera without lens model has no coefficients to free
  options.robust = parameterAsBool( parameters, QStringLiteral( "ROBUST" ), context );
  options.blunderThreshold = parameterAsDouble( parameters, QStringLiteral( "BLUNDER_W" ), context );
  const double defaultSigma = parameterAsDouble( parameters, QStringLiteral( "SIGMA_PX" ), context );

  std::unique_ptr<QgsProcessingFeatureSource> gcpSource( parameterAsSource( parameters, QStringLiteral( "GCPS" ), context ) );
  std::unique_ptr<QgsProcessingFeatureSource> observationSource( parameterAsSource( parameters, QStringLiteral( "OBSERVATIONS" ), context ) );
  if ( !gcpSource )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "GCPS" ) ) );
  if ( !observationSource )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "OBSERVATIONS" ) ) );
  const QVector<GeoStationProcessing::GroundPointRecord> ground = GeoStationProcessing::readGroundPoints( gcpSource.get(), QObject::tr( "control" ), crs, context.transformContext(), feedback );
  const GeoStationProcessing::ObservationTable table = GeoStationProcessing::readObservations( observationSource.get(), QObject::tr( "observations" ), feedback );

  std::vector<geostation::ControlPoint> control;
  for ( const GeoStationProcessing::GroundPointRecord &g : ground )
    control.push_back( { g.pointId.toStdString(), g.world, g.sigmaM, g.check } );
  std::vector<geostation::ImagePoint> observations;
  for ( const GeoStationProcessing::ObservationRecord &r : table.rows )
    if ( r.imageId == imageId )
      observations.push_back( { r.pointId.toStdString(), r.pixel, r.sigmaPx > 0.0 ? r.sigmaPx : defaultSigma } );
  if ( observations.empty() )
    throw QgsProcessingException( QObject::tr( "The observations table has no rows for image %1." ).arg( imageId ) );
  // a scanned film's measurements are scan pixels; the camera model works in the frame its inner orientation gives
  if ( image.innerOrientation )
  {
    const Eigen::Matrix<double, 2, 3> nominalFromScan = geostation::nominalFromScanAffine( camera, *image.innerOrientation );
    for ( geostation::ImagePoint &o : observations )
      o.pixelInImage = nominalFromScan.leftCols<2>() * o.pixelInImage + nominalFromScan.col( 2 );
    feedback->pushInfo( QObject::tr( "%1 is a scanned film: its measurements go through its inner orientation; residuals are in the camera's nominal pixels." ).arg( imageId ) );
  }
  feedback->setProgress( 10 );

  geostation::ResectionSummary summary;
  summary = geostation::resectImage( camera, control, observations, options );
  if ( !summary.ok() )
    throw QgsProcessingException( QObject::tr( "Resection of %1 failed: %2" ).arg( imageId, QString::fromStdString( summary.message ) ) );
  feedback->setProgress( 80 );

  // The oriented block: this image's exterior, and its own camera if the interior changed.
  QString cameraId = QString::fromStdString( camera.id );
  for ( geostation::BlockImage &i : block.images )
    if ( i.id == image.id )
    {
      i.exterior = summary.exterior;
      bool interiorFree = false;
      for ( bool f : options.freeInterior )
        interiorFree |= f;
      if ( interiorFree )
      {
        geostation::Camera own = summary.camera;
        own.id = camera.id + "@" + i.id;
        block.cameras.erase( std::remove_if( block.cameras.begin(), block.cameras.end(), [&own]( const geostation::Camera & c ) { return c.id == own.id; } ), block.cameras.end() );
        block.cameras.push_back( own );
        i.cameraId = own.id;
        cameraId = QString::fromStdString( own.id );
      }
    }

  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  const QString htmlPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT_HTML" ), context );
  const QString blockPath = parameterAsFileOutput( parameters, QStringLiteral( "OUTPUT_BLOCK" ), context );
  QByteArray html;
  if ( !htmlPath.isEmpty() )
  {
    std::map<std::string, Eigen::Vector2d> measured;
    for ( const geostation::ImagePoint &o : observations )
      measured[o.pointId] = o.pixelInImage;
    html = GeoStationProcessing::resectionHtml( summary, imageId, camera, measured );
  }
  GeoStationProcessing::writeBlockAndReports( block, blockPath, { { reportPath, GeoStationProcessing::jsonReport( reportJson( summary, imageId, cameraId ) ) }, { htmlPath, html } } );
  feedback->setProgress( 100 );

  feedback->pushInfo( QObject::tr( "%1 oriented from %2 control points: sigma0 = %3 px, RMSE control %4 px." )
                      .arg( imageId ).arg( summary.controlCount ).arg( summary.sigma0, 0, 'f', 3 ).arg( summary.rmseControlPx, 0, 'f', 3 ) );
  feedback->pushInfo( QObject::tr( "X0 = %1 ± %2 m, Y0 = %3 ± %4 m, Z0 = %5 ± %6 m" )
                      .arg( summary.estimates[0], 0, 'f', 3 ).arg( summary.sigmas[0], 0, 'f', 3 ).arg( summary.estimates[1], 0, 'f', 3 ).arg( summary.sigmas[1], 0, 'f', 3 )
                      .arg( summary.estimates[2], 0, 'f', 3 ).arg( summary.sigmas[2], 0, 'f', 3 ) );
  if ( summary.checkCount )
    feedback->pushInfo( QObject::tr( "Check points: %1, RMSE %2 px, %3 m on the ground." ).arg( summary.checkCount ).arg( summary.rmseCheckPx, 0, 'f', 3 ).arg( summary.rmseCheckM, 0, 'f', 3 ) );
  if ( !summary.blunders.empty() )
    feedback->pushWarning( QString::fromStdString( summary.message ) );

  QStringList blunders;
  for ( const std::string &b : summary.blunders )
    blunders << QString::fromStdString( b );
  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT_BLOCK" ), blockPath );
  outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  outputs.insert( QStringLiteral( "REPORT_HTML" ), htmlPath );
  outputs.insert( QStringLiteral( "SIGMA0" ), summary.sigma0 );
  outputs.insert( QStringLiteral( "RMSE_CHECK_M" ), summary.checkCount ? QVariant( summary.rmseCheckM ) : QVariant() );
  outputs.insert( QStringLiteral( "BLUNDERS" ), blunders.join( ',' ) );
  return outputs;
}

} // namespace GeoStationProcessing
