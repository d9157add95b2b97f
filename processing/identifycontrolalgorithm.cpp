/***************************************************************************
  identifycontrolalgorithm.cpp - geostation:identify_control
 ***************************************************************************/
#include "identifycontrolalgorithm.h"

#include <QJsonArray>
#include <QJsonObject>

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include <Eigen/Geometry>

#include "dem/demintersection.h"
#include "identification/photoidentification.h"
#include "io/rasterfile.h"
#include "orientationreports.h"
#include "processingblock.h"
#include "processingtables.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

namespace
{
  QJsonObject reportJson( const geostation::PhotoIdentificationSummary &photo, const QString &imageId, bool guided )
  {
    const geostation::ControlIdentificationSummary &s = photo.identification;
    const geostation::ResectionSummary &r = s.resection;
    const int candidates = photo.candidates;
    QJsonArray parameters, residuals, notFound, rejected;
    for ( size_t i = 0; i < r.parameterNames.size() && i < r.estimates.size(); ++i )
      parameters.append( QJsonObject { { "name", QString::fromStdString( r.parameterNames[i] ) }, { "value", r.estimates[i] }, { "sigma", r.sigmas[i] },
        { "unit", i < 3 ? "m" : "deg" } } );
    for ( const geostation::IdentifiedControl &id : s.identified )
      residuals.append( QJsonObject { { "point_id", QString::fromStdString( id.pointId ) }, { "col", id.pixelInImage.x() }, { "row", id.pixelInImage.y() },
        { "col_resid_px", id.residualPx.x() }, { "row_resid_px", id.residualPx.y() }, { "resid_px", id.residualPx.norm() } } );
    for ( const geostation::PredictedControl &p : s.notFound )
      notFound.append( QJsonObject { { "point_id", QString::fromStdString( p.pointId ) }, { "predicted_col", p.pixelInImage.x() }, { "predicted_row", p.pixelInImage.y() } } );
    for ( const std::string &id : s.rejected )
      rejected.append( QString::fromStdString( id ) );
    return QJsonObject {
      { "algorithm", "geostation:identify_control" }, { "image_id", imageId }, { "approximate_orientation_used", guided },
      { "candidates", candidates }, { "triangles", static_cast<double>( s.triangles ) }, { "poses", static_cast<double>( s.poses ) },
      { "hypotheses_verified", s.hypothesesVerified }, { "pairs_found", static_cast<int>( photo.identified.size() ) },
      { "pairs_by_distance_lists", static_cast<int>( s.identified.size() ) }, { "measured_at_prediction", photo.relocated },
      { "found_only_at_prediction", photo.addedAtPrediction }, { "flagged", static_cast<int>( photo.flagged.size() ) }, { "claim_limit_px", photo.claimLimitPx },
      { "runner_up_pairs", s.runnerUpPairs },
      { "false_alarms", s.falseAlarms }, { "seconds", s.seconds }, { "pairs", residuals }, { "not_found", notFound }, { "rejected", rejected },
      { "sigma0_px", r.sigma0 }, { "iterations", r.iterations }, { "converged", r.converged }, { "parameters", parameters },
      { "rmse_control_px", r.rmseControlPx }, { "message", QString::fromStdString( s.message ) } };
  }
} // namespace

QString IdentifyControlAlgorithm::name() const
{
  return QStringLiteral( "identify_control" );
}

QString IdentifyControlAlgorithm::displayName() const
{
  return QObject::tr( "Identify ground control in a photo" );
}

QStringList IdentifyControlAlgorithm::tags() const
{
  return QObject::tr( "photogrammetry,control points,gcp,targets,identification,automatic,resection,monoplotting" ).split( ',' );
}

QString IdentifyControlAlgorithm::group() const
{
  return QObject::tr( "Adjustment" );
}

QString IdentifyControlAlgorithm::groupId() const
{
  return QStringLiteral( "adjustment" );
}

QString IdentifyControlAlgorithm::helpText() const
{
  return QObject::tr( "Finds the signalised control points of CONTROL in one photo of the block, with no point measured by hand. "
                      "Bright compact marks (targets) are detected in the image; triangles of neighbouring control points are "
                      "paired with triangles of neighbouring marks, each pairing gives the camera's pose, and the pose that puts "
                      "most control points on marks is verified by a robust resection. The camera's interior orientation must be "
                      "known; an orientation of the image in the block, if there is one, is used as an approximation "
                      "(USE_ORIENTATION) and only marks within SEARCH_RADIUS_PX of each prediction are considered.\n\n"
                      "Nothing is claimed that chance could explain: with fewer than about seven targets found, or two different "
                      "answers that fit almost equally well, the algorithm stops with a message and writes nothing.\n\n"
                      "CONTROL is a point layer or a table with point_id, X, Y, Z; without heights, a DEM gives them. OUTPUT is an "
                      "observations table (point_id, image_id, col, row, sigma_px, status) ready for geostation:resection: status "
                      "identified, flagged (a mark there, but further from its prediction than the others allow: for the operator "
                      "to look at, not a measurement) or not_found (the control point falls in the photo where no mark was found; "
                      "pred_col and pred_row give where). REPORT lists the pairs with residuals, the resection, and the search's counts; REPORT_HTML the same for reading, with the residual vectors over the photo.\n\n"
                      "Marks from MARK_MIN_PX to a tenth of the photo across are found (MARK_MAX_PX 0; give a size to look for less). "
                      "Once the pairs give the pose, every control point is measured again at its prediction, at the size the "
                      "marks have on the ground there, and the centre of a disc seen obliquely is taken for the disc's centre, "
                      "not its ellipse's." );
}

IdentifyControlAlgorithm *IdentifyControlAlgorithm::createInstance() const
{
  return new IdentifyControlAlgorithm();
}

void IdentifyControlAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "IMAGE" ), QObject::tr( "Image id" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "CONTROL" ), QObject::tr( "Ground control (PointZ, or point_id, X, Y, Z)" ), QList<int>() << QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM (heights of control without Z)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterBoolean( QStringLiteral( "USE_ORIENTATION" ), QObject::tr( "Use the image's orientation in the block as an approximation" ), true ) );
  auto advanced = [this]( QgsProcessingParameterDefinition * p ) {
    p->setFlags( p->flags() | QgsProcessingParameterDefinition::FlagAdvanced );
    addParameter( p );
  };
  advanced( new QgsProcessingParameterNumber( QStringLiteral( "SEARCH_RADIUS_PX" ), QObject::tr( "Search radius around predictions (px)" ), QgsProcessingParameterNumber::Double, 80.0, false, 1.0 ) );
  advanced( new QgsProcessingParameterNumber( QStringLiteral( "MARK_MIN_PX" ), QObject::tr( "Smallest mark diameter (px)" ), QgsProcessingParameterNumber::Double, 3.0, false, 1.0 ) );
  advanced( new QgsProcessingParameterNumber( QStringLiteral( "MARK_MAX_PX" ), QObject::tr( "Largest mark diameter (px; 0: a tenth of the photo)" ), QgsProcessingParameterNumber::Double, 0.0, false, 0.0, 200.0 ) );
  advanced( new QgsProcessingParameterNumber( QStringLiteral( "MIN_CONTRAST" ), QObject::tr( "Smallest mark contrast (grey levels)" ), QgsProcessingParameterNumber::Double, 30.0, false, 1.0 ) );
  advanced( new QgsProcessingParameterBoolean( QStringLiteral( "DARK_MARKS" ), QObject::tr( "Marks are dark on a bright background" ), false ) );
  advanced( new QgsProcessingParameterNumber( QStringLiteral( "MAX_CANDIDATES" ), QObject::tr( "Strongest marks kept" ), QgsProcessingParameterNumber::Integer, 60, false, 3, 1000 ) );
  advanced( new QgsProcessingParameterNumber( QStringLiteral( "MIN_PAIRS" ), QObject::tr( "Fewest pairs for an identification" ), QgsProcessingParameterNumber::Integer, 5, false, 4 ) );
  advanced( new QgsProcessingParameterNumber( QStringLiteral( "TOLERANCE_PX" ), QObject::tr( "Matching tolerance after the resection (px)" ), QgsProcessingParameterNumber::Double, 2.5, false, 0.1 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Identified control (observations)" ), QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
  addParameter( GeoStationProcessing::htmlReportParameter() );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "PAIRS_FOUND" ), QObject::tr( "Control points identified" ) ) );
}

QVariantMap IdentifyControlAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const QString imageId = parameterAsString( parameters, QStringLiteral( "IMAGE" ), context ).trimmed();
  const geostation::BlockImage &image = GeoStationProcessing::blockImage( block, imageId );
  const geostation::Camera &camera = block.cameraOf( image );
  GeoStationProcessing::requireImageFile( block, image );
  GeoStationProcessing::LoadedDem dem;
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
    dem = GeoStationProcessing::loadDem( demLayer->source(), block );
  std::unique_ptr<QgsProcessingFeatureSource> controlSource( parameterAsSource( parameters, QStringLiteral( "CONTROL" ), context ) );
  if ( !controlSource )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "CONTROL" ) ) );
  const QVector<GeoStationProcessing::GroundPointRecord> ground = GeoStationProcessing::readGroundPoints(
        controlSource.get(), QObject::tr( "control" ), GeoStationProcessing::blockCrs( block ), context.transformContext(), feedback,
        dem.dem ? geostation::demHeightAt( *dem.dem, *dem.blockToDem ) : GeoStationProcessing::HeightSource() );
  std::vector<geostation::ControlPoint> control;
  for ( const GeoStationProcessing::GroundPointRecord &g : ground )
    control.push_back( { g.pointId.toStdString(), g.world, g.sigmaM, false } );

  geostation::MarkCandidateOptions marks;
  marks.minDiameterPx = parameterAsDouble( parameters, QStringLiteral( "MARK_MIN_PX" ), context );
  marks.maxDiameterPx = parameterAsDouble( parameters, QStringLiteral( "MARK_MAX_PX" ), context );
  marks.minContrast = parameterAsDouble( parameters, QStringLiteral( "MIN_CONTRAST" ), context );
  marks.brightMark = !parameterAsBool( parameters, QStringLiteral( "DARK_MARKS" ), context );
  marks.maxCandidates = parameterAsInt( parameters, QStringLiteral( "MAX_CANDIDATES" ), context );
  geostation::ControlIdentificationOptions options;
  options.minPairs = parameterAsInt( parameters, QStringLiteral( "MIN_PAIRS" ), context );
  options.tolerancePx = parameterAsDouble( parameters, QStringLiteral( "TOLERANCE_PX" ), context );
  options.searchRadiusPx = parameterAsDouble( parameters, QStringLiteral( "SEARCH_RADIUS_PX" ), context );
  if ( parameterAsBool( parameters, QStringLiteral( "USE_ORIENTATION" ), context ) && image.exterior )
    options.approximate = *image.exterior;
  feedback->setProgress( 5 );

  // marks in the scan's pixels; the camera model works in the nominal frame of a scanned film's inner orientation
  geostation::PhotoIdentificationOptions identification;
  identification.marks = marks;
  identification.identification = options;
  geostation::PhotoIdentificationSummary result;
  std::optional<Eigen::Matrix<double, 2, 3>> nominalFromScan;
  if ( image.innerOrientation )
    nominalFromScan = geostation::nominalFromScanAffine( camera, *image.innerOrientation );
  const cv::Mat grey = geostation::markGrey( geostation::readRaster( block.imageFilePath( image ).string() ).pixels );
  feedback->setProgress( 30 );
  identification.identification.progress = GeoStationProcessing::progressOf( feedback ).part( 0.3, 0.9 );
  result = geostation::identifyControlInPhoto( grey, camera, nominalFromScan, control, identification );
  if ( result.identification.status == geostation::ControlIdentificationSummary::Status::Cancelled )
    throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );
  feedback->pushInfo( QObject::tr( "%1 mark candidates in %2." ).arg( result.candidates ).arg( imageId ) );
  const geostation::ControlIdentificationSummary &summary = result.identification;
  if ( !summary.ok() )
    throw QgsProcessingException( QObject::tr( "No control identified in %1: %2." ).arg( imageId, QString::fromStdString( summary.message ) ) );
  feedback->setProgress( 90 );

  QgsFields fields;
  for ( const char *name : { "point_id", "image_id" } )
    fields.append( QgsField( QString::fromLatin1( name ), QVariant::String ) );
  for ( const char *name : { "col", "row", "sigma_px" } )
    fields.append( QgsField( QString::fromLatin1( name ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kStatus ), QVariant::String ) );
  for ( const char *name : { "pred_col", "pred_row", "resid_px" } )
    fields.append( QgsField( QString::fromLatin1( name ), QVariant::Double ) );
  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::NoGeometry, QgsCoordinateReferenceSystem() );
  auto write = [&]( const std::string &pointId, const QVariant &col, const QVariant &row, const QVariant &sigma, const QString &status, const Eigen::Vector2d &predicted,
                    const QVariant &residual ) {
    QgsFeature f( fields );
    f.setAttributes( QgsAttributes() << QString::fromStdString( pointId ) << imageId << col << row << sigma << status << predicted.x() << predicted.y() << residual );
    sink.add( f );
  };
  // written in the image's own pixels (the scan's, for scanned film), as measured
  for ( const geostation::PhotoIdentifiedPoint &p : result.identified )
    write( p.pointId, p.pixelInFile.x(), p.pixelInFile.y(), p.sigmaPx, QStringLiteral( "identified" ), p.predictedInFile, ( p.predictedInFile - p.pixelInFile ).norm() );
  for ( const geostation::PhotoIdentifiedPoint &p : result.flagged )
    write( p.pointId, p.pixelInFile.x(), p.pixelInFile.y(), p.sigmaPx, QStringLiteral( "flagged" ), p.predictedInFile, ( p.predictedInFile - p.pixelInFile ).norm() );
  for ( const auto &[pointId, predicted] : result.notFound )
    write( pointId, QVariant(), QVariant(), QVariant(), QStringLiteral( "not_found" ), predicted, QVariant() );

  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  const QString htmlPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT_HTML" ), context );
  GeoStationProcessing::writeReports( { { reportPath, GeoStationProcessing::jsonReport( reportJson( result, imageId, options.approximate.has_value() ) ) },
                                        { htmlPath, htmlPath.isEmpty() ? QByteArray() : GeoStationProcessing::identifyControlHtml( result, imageId, grey.cols, grey.rows ) } } );
  feedback->pushInfo( QObject::tr( "%1 control points identified in %2 from %3 poses in %4 s (%5 measured at their predictions, %6 of them found only there); "
                                   "%7 flagged further than %8 px from their prediction; %9 more fall in the photo unfound." )
                      .arg( result.identified.size() ).arg( imageId ).arg( summary.poses ).arg( summary.seconds, 0, 'f', 1 ).arg( result.relocated )
                      .arg( result.addedAtPrediction ).arg( result.flagged.size() ).arg( identification.agreementPx ).arg( result.notFound.size() ) );
  if ( !summary.rejected.empty() )
    feedback->pushWarning( QObject::tr( "%1 paired control points were rejected by the resection as blunders." ).arg( summary.rejected.size() ) );
  feedback->setProgress( 100 );
  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), sink.destination() );
  outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  outputs.insert( QStringLiteral( "REPORT_HTML" ), htmlPath );
  outputs.insert( QStringLiteral( "PAIRS_FOUND" ), static_cast<int>( result.identified.size() ) );
  return outputs;
}

} // namespace GeoStationProcessing
