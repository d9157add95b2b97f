/***************************************************************************
  reviseroadsalgorithm.cpp - geostation:revise_roads
  -------------------------------------------------------------------------
  Parameters -> core/revision -> outputs. The map's features are read and
  carried into the block CRS first (each part of a multi-part line a road
  of its own); everything is computed before any output is created.
 ***************************************************************************/
#include "reviseroadsalgorithm.h"

#include <memory>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsfeaturesource.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include "dem/demintersection.h"
#include "maproads.h"
#include "processingblock.h"
#include "reviseroadsoutputs.h"
#include "revision/maprevision.h"

namespace GeoStationProcessing
{

QString ReviseRoadsAlgorithm::name() const { return QStringLiteral( "revise_roads" ); }
QString ReviseRoadsAlgorithm::displayName() const { return QObject::tr( "Revise a road map against a stereo pair" ); }
QStringList ReviseRoadsAlgorithm::tags() const { return QObject::tr( "road,map,revision,update,change,verification,stereo,extraction" ).split( ',' ); }
QString ReviseRoadsAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString ReviseRoadsAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString ReviseRoadsAlgorithm::helpText() const
{
  return QObject::tr( "Holds an existing road map (MAP, a line layer in any CRS) against an oriented stereo pair (LEFT, RIGHT) "
                      "and says, road by road, what the images show.\n\n"
                      "Each map road is carried into both images through the DEM or the terrain height the pair itself gives, "
                      "and checked every few pixels along its course: confirmed where a road band lies on it in both images "
                      "(within TOLERANCE_M, the map's own accuracy); moved where, within SHIFT_MAX_M of it, a band in the left "
                      "image shows one in the right image at its ground point (where another road joins, the band opens on that side: "
                      "a short gap between confirmed stretches is confirmed where the band, open on one side, runs on at their offset and width); "
                      "not_found otherwise; occluded where it is not found and the surface model (SURFACE, else the DEM) hides it "
                      "from a camera (a building, a tree, a hill); outside where the pair "
                      "does not see it. Each feature is split where its status changes. Confirmed and moved stretches are "
                      "measured again in 3-D from the band centres in both images.\n\n"
                      "OUTPUT: the map's features in the block CRS (LineStringZ), each stretch with revision (confirmed, "
                      "moved, not_found, occluded, outside, invalid_geometry), evidence (0-1: the share of its samples that agree), "
                      "shift_m, sigma_max (m; NULL where the map's course is kept), source_fid, map_part (the part of a multi-part "
                      "feature, from 0), map_from_m and map_to_m (where the stretch lies along the map line, metres from its first vertex) "
                      "and the map's attributes. "
                      "VERTICES (optional): each measured course's vertices (piece = the OUTPUT row, vertex, X, Y, Z, sx, sy, sz, "
                      "height_from: stereo where the rays were intersected, terrain where the road runs along the epipolar direction; "
                      "map_m: the place along the map line it was measured at). The revisions of overlapping pairs become one with "
                      "merge_revisions. "
                      "A feature without geometry is one row, invalid_geometry, without geometry. NEW: the roads the pair's "
                      "own extraction finds that no map road explains (method extracted); the pair is extracted only when NEW is asked for, "
                      "so a revision without it takes a fraction of the time. REPORT: length and count per "
                      "status, and how much was decided by the map against found by extraction.\n\n"
                      "Road widths, polarity and contrast as extract_roads' defaults (3 to 30 m); SHIFT_MAX_M by default 1.5 "
                      "times the widest road (45 m)." );
}

ReviseRoadsAlgorithm *ReviseRoadsAlgorithm::createInstance() const { return new ReviseRoadsAlgorithm(); }

void ReviseRoadsAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( GeoStationProcessing::blockParameter() );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "LEFT" ), QObject::tr( "Left image id" ) ) );
  addParameter( new QgsProcessingParameterString( QStringLiteral( "RIGHT" ), QObject::tr( "Right image id" ) ) );
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "MAP" ), QObject::tr( "Road map" ), QList<int>() << QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "DEM" ), QObject::tr( "DEM" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterRasterLayer( QStringLiteral( "SURFACE" ), QObject::tr( "Surface model for occlusion (DSM; empty: the DEM)" ), QVariant(), true ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SHIFT_MAX_M" ), QObject::tr( "Largest shift of a road (m; empty: 1.5 x the widest road)" ), QgsProcessingParameterNumber::Double, QVariant(), true, 0.01, 100000.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "TOLERANCE_M" ), QObject::tr( "The map's accuracy (m)" ), QgsProcessingParameterNumber::Double, 2.0, false, 0.0, 1000.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "ROAD_WIDTH_MIN_M" ), QObject::tr( "Narrowest road (m on the ground)" ), QgsProcessingParameterNumber::Double, 3.0, false, 0.01, 1000.0 ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "ROAD_WIDTH_MAX_M" ), QObject::tr( "Widest road (m on the ground)" ), QgsProcessingParameterNumber::Double, 30.0, false, 0.01, 1000.0 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Revised map" ), QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "NEW" ), QObject::tr( "New roads" ), QgsProcessing::TypeVectorLine, QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "VERTICES" ), QObject::tr( "Vertices of the measured courses" ), QgsProcessing::TypeVector, QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
}

QVariantMap ReviseRoadsAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const geostation::Block block = GeoStationProcessing::loadBlock( parameterAsFile( parameters, QStringLiteral( "BLOCK" ), context ) );
  const geostation::BlockImage &left = GeoStationProcessing::blockImage( block, parameterAsString( parameters, QStringLiteral( "LEFT" ), context ).trimmed() );
  const geostation::BlockImage &right = GeoStationProcessing::blockImage( block, parameterAsString( parameters, QStringLiteral( "RIGHT" ), context ).trimmed() );
  if ( left.id == right.id )
    throw QgsProcessingException( QObject::tr( "LEFT and RIGHT are the same image (%1): a stereo pair needs two." ).arg( QString::fromStdString( left.id ) ) );
  if ( !left.exterior || !right.exterior )
    throw QgsProcessingException( QObject::tr( "The pair is not oriented: map revision carries the map into the images through their orientation." ) );
  std::unique_ptr<QgsProcessingFeatureSource> map( parameterAsSource( parameters, QStringLiteral( "MAP" ), context ) );
  if ( !map )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "MAP" ) ) );

  geostation::MapRevisionOptions options;
  const double minM = parameterAsDouble( parameters, QStringLiteral( "ROAD_WIDTH_MIN_M" ), context ), maxM = parameterAsDouble( parameters, QStringLiteral( "ROAD_WIDTH_MAX_M" ), context );
  if ( !( maxM >= minM ) )
    throw QgsProcessingException( QObject::tr( "ROAD_WIDTH_MAX_M (%1 m) is less than ROAD_WIDTH_MIN_M (%2 m)." ).arg( maxM ).arg( minM ) );
  options.network.roadWidthM = std::make_pair( minM, maxM );
  options.toleranceM = parameterAsDouble( parameters, QStringLiteral( "TOLERANCE_M" ), context );
  options.findNewRoads = outputRequested( parameters, QStringLiteral( "NEW" ) ); // the pair is extracted only for them
  if ( GeoStationProcessing::hasParameterValue( parameters, QStringLiteral( "SHIFT_MAX_M" ) ) )
    options.shiftMaxM = parameterAsDouble( parameters, QStringLiteral( "SHIFT_MAX_M" ), context );
  GeoStationProcessing::LoadedDem dem;
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
    dem = GeoStationProcessing::loadDem( demLayer->source(), block );
  if ( dem.dem )
    options.network.terrain = geostation::demHeightAt( *dem.dem, *dem.blockToDem );
  GeoStationProcessing::LoadedDem surface;
  if ( QgsRasterLayer *surfaceLayer = parameterAsRasterLayer( parameters, QStringLiteral( "SURFACE" ), context ) )
  {
    if ( !dem.dem )
      throw QgsProcessingException( QObject::tr( "SURFACE needs a DEM too: the roads' heights come from the DEM, the surface only says what hides them." ) );
    surface = GeoStationProcessing::loadDem( surfaceLayer->source(), block );
  }
  const GeoStationProcessing::LoadedDem &occluding = surface.dem ? surface : dem;
  if ( occluding.dem )
    options.surface = [&occluding]( const geostation::Ray &ray ) -> std::optional<Eigen::Vector3d>
    {
      const geostation::DemIntersection hit = geostation::intersectRayWithDem( ray, *occluding.dem, *occluding.blockToDem );
      return hit.hit() ? std::optional<Eigen::Vector3d>( hit.point ) : std::nullopt;
    };

  const QgsCoordinateReferenceSystem blockCrs = GeoStationProcessing::blockCrs( block );
  const QgsCoordinateReferenceSystem mapCrs = map->sourceCrs().isValid() ? map->sourceCrs() : blockCrs;
  if ( !map->sourceCrs().isValid() )
    feedback->pushWarning( QObject::tr( "MAP has no CRS; its coordinates are taken to be in the block CRS %1." ).arg( blockCrs.userFriendlyIdentifier() ) );
  const GeoStationProcessing::MapRoads lines = GeoStationProcessing::readMapRoads( *map, QgsCoordinateTransform( mapCrs, blockCrs, context.transformContext() ), feedback );
  if ( feedback->isCanceled() )
    throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );

  const geostation::OrientedImage a = GeoStationProcessing::orientedImage( block, left ), b = GeoStationProcessing::orientedImage( block, right );
  const geostation::Progress progress = GeoStationProcessing::progressOf( feedback ).part( 0.0, 0.9 );
  const geostation::MapRevisionSummary s = geostation::reviseRoads( GeoStationProcessing::openImageFile( block, left ), GeoStationProcessing::openImageFile( block, right ), a, b, lines.roads, options, progress );
  if ( s.cancelled )
    throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );
  bool anySeen = false;
  for ( const geostation::RevisedPiece &p : s.pieces )
    anySeen = anySeen || ( p.status != geostation::RevisionStatus::Outside && p.status != geostation::RevisionStatus::InvalidGeometry );
  if ( !anySeen && !lines.roads.empty() )
    feedback->pushWarning( QObject::tr( "No road of the map lies where both images see the ground: every feature is outside." ) );

  // outputs, only now
  const GeoStationProcessing::RevisedMapFields fields = GeoStationProcessing::revisedMapFields( map->fields() );
  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields.fields, QgsWkbTypes::LineStringZ, blockCrs );
  for ( const geostation::RevisedPiece &p : s.pieces )
  {
    QgsFeature f = GeoStationProcessing::revisedMapFeature( p, lines.source[p.road], lines.part[p.road], fields );
    sink.add( f );
  }
  sink.close( true );
  QVariantMap outputs { { QStringLiteral( "OUTPUT" ), sink.destination() } };

  if ( outputRequested( parameters, QStringLiteral( "VERTICES" ) ) )
  {
    const QgsFields vertexFields = GeoStationProcessing::revisionVertexFields();
    OutputSink vertexSink = openOutput( parameters, QStringLiteral( "VERTICES" ), context, vertexFields, QgsWkbTypes::NoGeometry, QgsCoordinateReferenceSystem() );
    for ( size_t i = 0; i < s.pieces.size(); ++i )
    {
      QgsFeatureList rows = GeoStationProcessing::revisionVertexRows( s.pieces[i], static_cast<int>( i + 1 ), vertexFields );
      vertexSink.add( rows );
    }
    outputs.insert( QStringLiteral( "VERTICES" ), vertexSink.destination() );
  }

  if ( outputRequested( parameters, QStringLiteral( "NEW" ) ) )
  {
    const QgsFields newFields = GeoStationProcessing::newRoadFields();
    OutputSink newSink = openOutput( parameters, QStringLiteral( "NEW" ), context, newFields, QgsWkbTypes::LineStringZ, blockCrs );
    for ( size_t i = 0; i < s.newRoads.size(); ++i )
    {
      QgsFeature f = GeoStationProcessing::newRoadFeature( s.newRoads[i], static_cast<int>( i + 1 ), newFields );
      newSink.add( f );
    }
    outputs.insert( QStringLiteral( "NEW" ), newSink.destination() );
  }
  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  if ( !reportPath.isEmpty() )
  {
    GeoStationProcessing::writeReport( GeoStationProcessing::reviseRoadsReport( s, QString::fromStdString( left.id ), QString::fromStdString( right.id ), map->featureCount() ), reportPath );
    outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  }
  feedback->pushInfo( QObject::tr( "%1 m confirmed, %2 m moved, %3 m not found, %4 m outside; %5 new roads." )
                      .arg( s.lengthM( geostation::RevisionStatus::Confirmed ), 0, 'f', 0 ).arg( s.lengthM( geostation::RevisionStatus::Moved ), 0, 'f', 0 )
                      .arg( s.lengthM( geostation::RevisionStatus::NotFound ), 0, 'f', 0 ).arg( s.lengthM( geostation::RevisionStatus::Outside ), 0, 'f', 0 )
                      .arg( s.newRoads.size() ) );
  return outputs;
}

} // namespace GeoStationProcessing
