/***************************************************************************
  matchpointsalgorithm.cpp - geostation:match_points
  -------------------------------------------------------------------------
  Points measured in reference images are found in target images by area
  matching (core/matching): along the epipolar band between two oriented
  images, otherwise in a 2-D window around an approximate position. The
  output is an observation table (docs/conventions.md §6) ready for intersect: the
  reference rows and every match, with score and sigma_px.
 ***************************************************************************/
#include "matchpointsalgorithm.h"

#include <memory>
#include <optional>

#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include "dem/demintersection.h"
#include "workstation/pointmatcher.h"
#include "processingblock.h"
#include "processingtables.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

QString MatchPointsAlgorithm::name() const { return QStringLiteral( "match_points" ); }
QString MatchPointsAlgorithm::displayName() const { return QObject::tr( "Match points into other images" ); }
QStringList MatchPointsAlgorithm::tags() const { return QObject::tr( "matching,correlation,ncc,least squares,lsm,epipolar,conjugate,tie points" ).split( ',' ); }
QString MatchPointsAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString MatchPointsAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString MatchPointsAlgorithm::helpText() const
{
  return QObject::tr( "Finds points measured in reference images (OBSERVATIONS: point_id, image_id, col, row) in other images "
                      "of the block. TARGETS lists the image ids to search (comma-separated; default: the other images of the "
                      "reference image's station).\n\n"
                      "When both images are oriented the search runs along the epipolar band (the curve for depths MIN_DEPTH_M "
                      "to MAX_DEPTH_M, and BAND_PX parallels on each side); otherwise it searches SEARCH_RADIUS pixels around "
                      "approx_col, approx_row given per point. METHOD is cc, ncc, wcc or wncc (thesis eqs. 5.1-5.4) on a "
                      "WINDOW_W x WINDOW_H window (15 x 15; 15 x 3 for road lines); the best score above MIN_SCORE is refined "
                      "by a parabola and, with LSM, by least-squares matching started from the peak, the approximate position "
                      "and the next peaks; a least-squares match must fit well, keep a plausible shape, stay within the search "
                      "radius and match back to the reference point within half a pixel. With a DEM and oriented images, the "
                      "window's shape in the target image is predicted on the terrain (oblique and close-range pairs), and the "
                      "square and the predicted window compete: the one that correlates better is refined.\n\n"
                      "OUTPUT holds the reference rows (status reference) and one row per point and target image with status: "
                      "lsm (least squares converged and passed its checks), correlation (peak only: LSM off, or a line or edge "
                      "LSM cannot fix), or why there is no match (no_peak, ambiguous, diverged, inconsistent, outside; no col/row, "
                      "with the reason). geostation:intersect reads it as it is and leaves the failed rows out." );
}

MatchPointsAlgorithm *MatchPointsAlgorithm::createInstance() const { return new MatchPointsAlgorithm(); }

void MatchPointsAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "OBSERVATIONS" ), QObject::tr( "Points in reference images (point_id, image_id, col, row)" ),
                QList<int>() << QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "TARGETS" ), QObject::tr( "Target image ids (comma-separated; default: the station's other images)" ), QVariant(), false, true ) );
  addParameter( new QgsProcessingParameterEnum( QStringLiteral( "METHOD" ), QObject::tr( "Similarity" ),
                QStringList { QStringLiteral( "cc" ), QStringLiteral( "ncc" ), QStringLiteral( "wcc" ), QStringLiteral( "wncc" ) }, false, QStringLiteral( "ncc" ), false, true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "WINDOW_W" ), QObject::tr( "Window width (odd, px)" ), QgsProcessingParameterNumber::Integer, 15, false, 3, 101 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "WINDOW_H" ), QObject::tr( "Window height (odd, px)" ), QgsProcessingParameterNumber::Integer, 15, false, 1, 101 ) );
  addParameter( new QgsProcessingParameterBoolean( QStringLiteral( "LSM" ), QObject::tr( "Refine by least-squares matching" ), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MIN_SCORE" ), QObject::tr( "Minimum correlation" ), QgsProcessingParameterNumber::Double, 0.7, false, -1.0, 1.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MIN_DEPTH_M" ), QObject::tr( "Epipolar search: nearest depth (m)" ), QgsProcessingParameterNumber::Double, 2.0, false, 0.01 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "MAX_DEPTH_M" ), QObject::tr( "Epipolar search: farthest depth (m)" ), QgsProcessingParameterNumber::Double, 50.0, false, 0.02 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "BAND_PX" ), QObject::tr( "Epipolar search: parallels on each side (px)" ), QgsProcessingParameterNumber::Integer, 1, false, 0, 20 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SEARCH_RADIUS" ), QObject::tr( "2-D search radius, unoriented images (px)" ), QgsProcessingParameterNumber::Double, 20.0, false, 1.0, 500.0 ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM (oriented images: the window's shape predicted on the terrain)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "REFERENCE_SIGMA_PX" ), QObject::tr( "sigma_px of the reference measurements" ), QgsProcessingParameterNumber::Double, 0.5, false, 0.001 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Observations" ), QgsProcessing::TypeVector ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "MATCHED_COUNT" ), QObject::tr( "Matches" ) ) );
  addOutput( new QgsProcessingOutputNumber( QStringLiteral( "NO_MATCH_COUNT" ), QObject::tr( "Points without a match" ) ) );
}

QVariantMap MatchPointsAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "OBSERVATIONS" ), context ) );
  if ( !source )
    throw QgsProcessingException( QObject::tr( "The observation table cannot be read." ) );
  const GeoStationProcessing::ObservationTable table = GeoStationProcessing::readObservations( source.get(), QObject::tr( "OBSERVATIONS" ), feedback );
  const int approxCol = table.extraFields.lookupField( QStringLiteral( "approx_col" ) ), approxRow = table.extraFields.lookupField( QStringLiteral( "approx_row" ) );

  geostation::PointMatchOptions options;
  geostation::AreaMatchOptions &area = options.area;
  area.measure = *geostation::similarityMeasureFromName( parameterAsEnumString( parameters, QStringLiteral( "METHOD" ), context ).toStdString() );
  area.windowWidth = parameterAsInt( parameters, QStringLiteral( "WINDOW_W" ), context );
  area.windowHeight = parameterAsInt( parameters, QStringLiteral( "WINDOW_H" ), context );
  area.lsm = parameterAsBool( parameters, QStringLiteral( "LSM" ), context );
  area.minScore = parameterAsDouble( parameters, QStringLiteral( "MIN_SCORE" ), context );
  area.bandHalfWidthPx = parameterAsInt( parameters, QStringLiteral( "BAND_PX" ), context );
  options.epipolar.minDistanceM = parameterAsDouble( parameters, QStringLiteral( "MIN_DEPTH_M" ), context );
  options.epipolar.maxDistanceM = parameterAsDouble( parameters, QStringLiteral( "MAX_DEPTH_M" ), context );
  if ( !( options.epipolar.maxDistanceM > options.epipolar.minDistanceM ) )
    throw QgsProcessingException( QObject::tr( "MAX_DEPTH_M must be larger than MIN_DEPTH_M." ) );
  options.searchRadiusPx = parameterAsDouble( parameters, QStringLiteral( "SEARCH_RADIUS" ), context );
  GeoStationProcessing::LoadedDem dem;
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
    dem = GeoStationProcessing::loadDem( demLayer->source(), block );
  if ( dem.dem )
    options.terrain = geostation::demGroundOfPixel( *dem.dem, *dem.blockToDem );
  const double referenceSigma = parameterAsDouble( parameters, QStringLiteral( "REFERENCE_SIGMA_PX" ), context );
  QStringList targetIds;
  for ( const QString &id : parameterAsString( parameters, QStringLiteral( "TARGETS" ), context ).split( ',', Qt::SkipEmptyParts ) )
    targetIds << id.trimmed();
  for ( const QString &id : targetIds )
    GeoStationProcessing::blockImage( block, id ); // unknown ids fail here, before any output
  // images are prepared once and kept within the cache's budget (the last 18, 1 GiB); an image too large to prepare
  // whole is read in the window a match needs
  geostation::MatchImageCache cache;
  std::unique_ptr<geostation::PointMatcher> matcher;
  matcher = std::make_unique<geostation::PointMatcher>( block, options, cache );

  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kPointId ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kImageId ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kCol ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kRow ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kSigmaPx ), QVariant::Double ) );
  fields.append( QgsField( QStringLiteral( "score" ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kStatus ), QVariant::String ) );
  fields.append( QgsField( QStringLiteral( "reason" ), QVariant::String ) );
  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::NoGeometry, QgsCoordinateReferenceSystem() );
  // a failed match is a row too, with its status and reason and no col/row (docs/conventions.md §8)
  const auto write = [&]( const QString &pointId, const QString &imageId, const std::optional<Eigen::Vector2d> &pixel, double sigma, double score, const QString &status,
                          const QString &reason )
  {
    QgsFeature f( fields );
    const QVariant none;
    f.setAttributes( QgsAttributes() << pointId << imageId << ( pixel ? QVariant( pixel->x() ) : none ) << ( pixel ? QVariant( pixel->y() ) : none )
                     << ( pixel ? QVariant( sigma ) : none ) << score << status << ( reason.isEmpty() ? none : QVariant( reason ) ) );
    sink.add( f );
  };

  long matched = 0, unmatched = 0;
  StatusTally statusCounts;
  for ( int i = 0; i < table.rows.size(); ++i )
  {
    if ( feedback->isCanceled() )
      break;
    feedback->setProgress( 100.0 * i / std::max( 1, table.rows.size() ) );
    const GeoStationProcessing::ObservationRecord &r = table.rows[i];
    const geostation::BlockImage &reference = GeoStationProcessing::blockImage( block, r.imageId );
    write( r.pointId, r.imageId, r.pixel, r.sigmaPx > 0 ? r.sigmaPx : referenceSigma, 1.0, QStringLiteral( "reference" ), QString() );
    QStringList targets = targetIds;
    if ( targets.isEmpty() )
      for ( const geostation::BlockImage &other : block.images )
        if ( other.id != reference.id && !reference.stationId.empty() && other.stationId == reference.stationId )
          targets << QString::fromStdString( other.id );
    std::optional<Eigen::Vector2d> approximate;
    if ( approxCol >= 0 && approxRow >= 0 )
    {
      bool okCol = false, okRow = false;
      const double col = r.extra.value( approxCol ).toString().toDouble( &okCol ), row = r.extra.value( approxRow ).toString().toDouble( &okRow );
      if ( okCol && okRow )
        approximate = Eigen::Vector2d( col, row );
    }
    for ( const QString &targetId : targets )
    {
      if ( targetId == r.imageId )
        continue;
      const geostation::BlockImage &target = GeoStationProcessing::blockImage( block, targetId );
      geostation::AreaMatch m;
      if ( !( reference.exterior && target.exterior ) && approxCol >= 0 && approxRow >= 0 && !approximate )
      {
        m.status = geostation::MatchStatus::Outside;
        m.message = "approx_col and approx_row are not numbers";
      }
      else
        m = matcher->match( reference, r.pixel, target, approximate );
      const QString status = QString::fromStdString( geostation::matchStatusName( m.status ) ), reason = QString::fromStdString( m.message );
      statusCounts.add( status );
      if ( m.matched() )
      {
        write( r.pointId, targetId, m.pixelInImage, std::max( 0.02, m.sigmaPx ), m.score, status, reason );
        ++matched;
      }
      else
      {
        write( r.pointId, targetId, std::nullopt, 0.0, m.score, status, reason );
        feedback->pushWarning( QObject::tr( "%1 in %2: no match, %3 (%4)." ).arg( r.pointId, targetId, status, reason ) );
        ++unmatched;
      }
    }
  }
  feedback->pushInfo( QObject::tr( "%1 matches, %2 without a match (%3)." ).arg( matched ).arg( unmatched ).arg( statusCounts.text() ) );
  QVariantMap outputs;
  outputs.insert( QStringLiteral( "OUTPUT" ), sink.destination() );
  outputs.insert( QStringLiteral( "MATCHED_COUNT" ), static_cast<qlonglong>( matched ) );
  outputs.insert( QStringLiteral( "NO_MATCH_COUNT" ), static_cast<qlonglong>( unmatched ) );
  return outputs;
}

} // namespace GeoStationProcessing
