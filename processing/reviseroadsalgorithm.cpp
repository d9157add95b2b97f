/***************************************************************************
  reviseroadsalgorithm.cpp - geostation:revise_roads
  -------------------------------------------------------------------------
  Parameters -> core/revision -> outputs. The map's features are read and
  carried into the block CRS first (each part of a multi-part line a road
  of its own); everything is computed before any output is created.
 ***************************************************************************/
#include "reviseroadsalgorithm.h"

#include <cmath>
#include <map>
#include <memory>

#include <QJsonArray>
#include <QJsonObject>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsfeaturesource.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsrasterlayer.h>

#include "dem/demintersection.h"
#include "io/rasterfile.h"
#include "io/featureschema.h"
#include "processingblock.h"
#include "revision/maprevision.h"

namespace GeoStationProcessing
{

namespace
{
  bool hasValue( const QVariantMap &parameters, const QString &name )
  {
    const QVariant v = parameters.value( name );
    return v.isValid() && !v.isNull() && !v.toString().trimmed().isEmpty();
  }

  std::shared_ptr<const geostation::RasterReader> openImage( const geostation::Block &block, const geostation::BlockImage &image )
  {
    GeoStationProcessing::requireImageFile( block, image );
    return std::make_shared<const geostation::RasterReader>( block.imageFilePath( image ).string() );
  }

  //! The map's lines in the block CRS: one road per part, with the feature each came from.
  struct MapLines
  {
    std::vector<geostation::MapRoad> roads;
    std::vector<QgsFeature> source; //!< per road
  };

  MapLines readMap( QgsFeatureSource &map, const QgsCoordinateTransform &toBlock, QgsProcessingFeedback *feedback )
  {
    MapLines lines;
    QgsFeature f;
    QgsFeatureIterator it = map.getFeatures();
    while ( it.nextFeature( f ) )
    {
      if ( feedback->isCanceled() )
        break;
      QgsGeometry g = f.geometry();
      bool transformed = !g.isNull() && !g.isEmpty();
      if ( transformed )
      {
        try
        {
          g.transform( toBlock );
        }
        catch ( const QgsCsException & )
        {
          transformed = false;
        }
      }
      // each part a road; heights, where the map has them, are taken, else the terrain's
      const size_t before = lines.roads.size();
      const bool hasZ = transformed && QgsWkbTypes::hasZ( g.wkbType() );
      if ( transformed )
        for ( auto part = g.const_parts_begin(); part != g.const_parts_end(); ++part )
        {
          geostation::MapRoad road;
          for ( auto v = ( *part )->vertices_begin(); v != ( *part )->vertices_end(); ++v )
            road.vertices.emplace_back( ( *v ).x(), ( *v ).y(), hasZ && std::isfinite( ( *v ).z() ) ? ( *v ).z() : std::nan( "" ) );
          if ( !road.vertices.empty() )
          {
            lines.roads.push_back( road );
            lines.source.push_back( f );
          }
        }
      if ( lines.roads.size() == before )
      {
        lines.roads.emplace_back(); // no geometry: invalid_geometry, its row kept
        lines.source.push_back( f );
      }
    }
    return lines;
  }

  QgsGeometry lineZ( const std::vector<Eigen::Vector3d> &points )
  {
    QVector<double> x, y, z;
    for ( const Eigen::Vector3d &p : points )
    {
      x << p.x();
      y << p.y();
      z << ( std::isfinite( p.z() ) ? p.z() : 0.0 );
    }
    return QgsGeometry( new QgsLineString( x, y, z ) );
  }

  double sigmaMax( const std::vector<Eigen::Vector3d> &sigmas )
  {
    double m = 0.0;
    for ( const Eigen::Vector3d &s : sigmas )
      m = std::max( m, s.maxCoeff() );
    return m;
  }

  QJsonObject report( const geostation::MapRevisionSummary &s, const QString &left, const QString &right, int features )
  {
    QJsonObject byStatus;
    std::map<std::string, std::pair<int, double>> counts;
    for ( const geostation::RevisedPiece &p : s.pieces )
    {
      auto &c = counts[geostation::revisionStatusName( p.status )];
      ++c.first;
      c.second += p.lengthM();
    }
    for ( const auto &[name, c] : counts )
      byStatus.insert( QString::fromStdString( name ), QJsonObject { { "pieces", c.first }, { "length_m", c.second } } );
    double newLength = 0.0;
    for ( const geostation::NetworkLine &l : s.newRoads )
      newLength += l.lengthM();
    const double decided = s.lengthM( geostation::RevisionStatus::Confirmed ) + s.lengthM( geostation::RevisionStatus::Moved ) +
                           s.lengthM( geostation::RevisionStatus::NotFound );
    return QJsonObject { { "left", left }, { "right", right }, { "map_features", features }, { "samples", s.samples },
                         { "by_status", byStatus }, { "new", QJsonObject { { "lines", static_cast<int>( s.newRoads.size() ) }, { "length_m", newLength } } },
                         { "decided_by_the_map_m", decided }, { "found_by_extraction_m", newLength },
                         { "shift_max_m", s.shiftMaxM }, { "tolerance_m", s.toleranceM }, { "ground_pixel_m", s.groundPixelM },
                         { "mean_height_m", s.extraction.meanHeightM }, { "seconds", s.seconds },
                         { "extracted", !s.extraction.extraction.linesA.empty() || !s.newRoads.empty() } };
  }
}

QString ReviseRoadsAlgorithm::name() const { return QStringLiteral( "revise_roads" ); }
QString ReviseRoadsAlgorithm::displayName() const { return QObject::tr( "Revise a road map against a stereo pair" ); }
QStringList ReviseRoadsAlgorithm::tags() const { return QObject::tr( "road,map,revision,update,change,verification,stereo,extraction" ).split( ',' ); }
QString ReviseRoadsAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString ReviseRoadsAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString ReviseRoadsAlgorithm::shortHelpString() const
{
  return QObject::tr( "Holds an existing road map (MAP, a line layer in any CRS) against an oriented stereo pair (LEFT, RIGHT) "
                      "and says, road by road, what the images show.\n\n"
                      "Each map road is carried into both images through the DEM or the terrain height the pair itself gives, "
                      "and checked every few pixels along its course: confirmed where a road band lies on it in both images "
                      "(within TOLERANCE_M, the map's own accuracy); moved where, within SHIFT_MAX_M of it, a band in the left "
                      "image shows one in the right image at its ground point; not_found otherwise; outside where the pair "
                      "does not see it. Each feature is split where its status changes. Confirmed and moved stretches are "
                      "measured again in 3-D from the band centres in both images.\n\n"
                      "OUTPUT: the map's features in the block CRS (LineStringZ), each stretch with revision (confirmed, "
                      "moved, not_found, outside, invalid_geometry), evidence (0-1: the share of its samples that agree), "
                      "shift_m, sigma_max (m; NULL where the map's course is kept), source_fid and the map's attributes. "
                      "VERTICES (optional): each measured course's vertices (piece = the OUTPUT row, vertex, X, Y, Z, sx, sy, sz, "
                      "height_from: stereo where the rays were intersected, terrain where the road runs along the epipolar direction). "
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
  if ( hasValue( parameters, QStringLiteral( "SHIFT_MAX_M" ) ) )
    options.shiftMaxM = parameterAsDouble( parameters, QStringLiteral( "SHIFT_MAX_M" ), context );
  GeoStationProcessing::LoadedDem dem;
  if ( QgsRasterLayer *demLayer = parameterAsRasterLayer( parameters, QStringLiteral( "DEM" ), context ) )
    dem = GeoStationProcessing::loadDem( demLayer->source(), block );
  if ( dem.dem )
    options.network.terrain = geostation::demHeightAt( *dem.dem, *dem.blockToDem );

  const QgsCoordinateReferenceSystem blockCrs = GeoStationProcessing::blockCrs( block );
  const QgsCoordinateReferenceSystem mapCrs = map->sourceCrs().isValid() ? map->sourceCrs() : blockCrs;
  if ( !map->sourceCrs().isValid() )
    feedback->pushWarning( QObject::tr( "MAP has no CRS; its coordinates are taken to be in the block CRS %1." ).arg( blockCrs.userFriendlyIdentifier() ) );
  const MapLines lines = readMap( *map, QgsCoordinateTransform( mapCrs, blockCrs, context.transformContext() ), feedback );
  if ( feedback->isCanceled() )
    throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );

  const geostation::OrientedImage a = GeoStationProcessing::orientedImage( block, left ), b = GeoStationProcessing::orientedImage( block, right );
  const geostation::ExtractionProgress progress = [feedback]( double f ) { feedback->setProgress( 90.0 * f ); return !feedback->isCanceled(); };
  const geostation::MapRevisionSummary s = geostation::reviseRoads( openImage( block, left ), openImage( block, right ), a, b, lines.roads, options, progress );
  if ( s.cancelled )
    throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );
  bool anySeen = false;
  for ( const geostation::RevisedPiece &p : s.pieces )
    anySeen = anySeen || ( p.status != geostation::RevisionStatus::Outside && p.status != geostation::RevisionStatus::InvalidGeometry );
  if ( !anySeen && !lines.roads.empty() )
    feedback->pushWarning( QObject::tr( "No road of the map lies where both images see the ground: every feature is outside." ) );

  // outputs, only now
  // the map's fields but its GeoPackage fid, which a feature split in pieces would repeat (source_fid keeps it)
  QgsFields fields;
  QList<int> copied;
  for ( int i = 0; i < map->fields().count(); ++i )
    if ( map->fields().at( i ).name().compare( QLatin1String( "fid" ), Qt::CaseInsensitive ) != 0 )
    {
      fields.append( map->fields().at( i ) );
      copied << i;
    }
  for ( const QString &name : { QStringLiteral( "source_fid" ), QStringLiteral( "revision" ), QStringLiteral( "evidence" ), QStringLiteral( "shift_m" ), QStringLiteral( "sigma_max" ) } )
    if ( fields.lookupField( name ) >= 0 )
      throw QgsProcessingException( QObject::tr( "MAP has a field named %1, which the output adds: rename it first." ).arg( name ) );
  fields.append( QgsField( QStringLiteral( "source_fid" ), QVariant::LongLong ) );
  fields.append( QgsField( QStringLiteral( "revision" ), QVariant::String ) );
  fields.append( QgsField( QStringLiteral( "evidence" ), QVariant::Double ) );
  fields.append( QgsField( QStringLiteral( "shift_m" ), QVariant::Double ) );
  fields.append( QgsField( QStringLiteral( "sigma_max" ), QVariant::Double ) );
  QString destination;
  std::unique_ptr<QgsFeatureSink> sink( parameterAsSink( parameters, QStringLiteral( "OUTPUT" ), context, destination, fields, QgsWkbTypes::LineStringZ, blockCrs ) );
  if ( !sink )
    throw QgsProcessingException( invalidSinkError( parameters, QStringLiteral( "OUTPUT" ) ) );
  for ( const geostation::RevisedPiece &p : s.pieces )
  {
    const QgsFeature &source = lines.source[p.road];
    QgsFeature f( fields );
    QgsAttributes attributes;
    for ( const int i : copied )
      attributes << source.attribute( i );
    attributes << source.id() << QString::fromStdString( geostation::revisionStatusName( p.status ) ) << p.evidence << p.shiftM
               << ( p.sigmaM.empty() ? QVariant() : QVariant( sigmaMax( p.sigmaM ) ) );
    f.setAttributes( attributes );
    if ( p.status != geostation::RevisionStatus::InvalidGeometry )
      f.setGeometry( lineZ( p.course ) );
    if ( !sink->addFeature( f, QgsFeatureSink::FastInsert ) )
      throw QgsProcessingException( writeFeatureError( sink.get(), parameters, QStringLiteral( "OUTPUT" ) ) );
  }
  sink.reset();
  GeoStationProcessing::storeMissingGeometriesAsNull( destination );
  QVariantMap outputs { { QStringLiteral( "OUTPUT" ), destination } };

  // the measured courses' vertices with their sigmas: piece = the OUTPUT row (1, 2, ...)
  if ( outputRequested( parameters, QStringLiteral( "VERTICES" ) ) )
  {
    namespace fs = geostation::featureschema;
    QgsFields vertexFields;
    for ( const auto &[name, type] : std::vector<std::pair<const char *, QVariant::Type>> { { "piece", QVariant::Int }, { fs::kVertex, QVariant::Int }, { fs::kX, QVariant::Double },
          { fs::kY, QVariant::Double }, { fs::kZ, QVariant::Double }, { fs::kSx, QVariant::Double }, { fs::kSy, QVariant::Double }, { fs::kSz, QVariant::Double },
          { "height_from", QVariant::String } } )
      vertexFields.append( QgsField( QString::fromLatin1( name ), type ) );
    QString vertexDestination;
    std::unique_ptr<QgsFeatureSink> vertexSink( parameterAsSink( parameters, QStringLiteral( "VERTICES" ), context, vertexDestination, vertexFields, QgsWkbTypes::NoGeometry, QgsCoordinateReferenceSystem() ) );
    if ( !vertexSink )
      throw QgsProcessingException( invalidSinkError( parameters, QStringLiteral( "VERTICES" ) ) );
    for ( size_t i = 0; i < s.pieces.size(); ++i )
    {
      const geostation::RevisedPiece &p = s.pieces[i];
      for ( size_t k = 0; k < p.sigmaM.size() && k < p.course.size(); ++k )
      {
        QgsFeature v( vertexFields );
        v.setAttributes( QgsAttributes() << static_cast<int>( i + 1 ) << static_cast<int>( k ) << p.course[k].x() << p.course[k].y() << p.course[k].z() << p.sigmaM[k].x()
                         << p.sigmaM[k].y() << p.sigmaM[k].z() << ( k < p.heightByStereo.size() && p.heightByStereo[k] ? QStringLiteral( "stereo" ) : QStringLiteral( "terrain" ) ) );
        if ( !vertexSink->addFeature( v, QgsFeatureSink::FastInsert ) )
          throw QgsProcessingException( writeFeatureError( vertexSink.get(), parameters, QStringLiteral( "VERTICES" ) ) );
      }
    }
    outputs.insert( QStringLiteral( "VERTICES" ), vertexDestination );
  }

  QgsFields newFields;
  newFields.append( QgsField( QStringLiteral( "line_id" ), QVariant::Int ) );
  newFields.append( QgsField( QStringLiteral( "method" ), QVariant::String ) );
  newFields.append( QgsField( QStringLiteral( "length_m" ), QVariant::Double ) );
  newFields.append( QgsField( QStringLiteral( "sigma_max" ), QVariant::Double ) );
  if ( outputRequested( parameters, QStringLiteral( "NEW" ) ) )
  {
    QString newDestination;
    std::unique_ptr<QgsFeatureSink> newSink( parameterAsSink( parameters, QStringLiteral( "NEW" ), context, newDestination, newFields, QgsWkbTypes::LineStringZ, blockCrs ) );
    if ( !newSink )
      throw QgsProcessingException( invalidSinkError( parameters, QStringLiteral( "NEW" ) ) );
    for ( size_t i = 0; i < s.newRoads.size(); ++i )
    {
      std::vector<Eigen::Vector3d> points;
      for ( const geostation::NetworkVertex &v : s.newRoads[i].vertices )
        points.push_back( v.point );
      QgsFeature f( newFields );
      f.setAttributes( QgsAttributes() << static_cast<int>( i + 1 ) << QStringLiteral( "extracted" ) << s.newRoads[i].lengthM() << s.newRoads[i].sigmaMaxM() );
      f.setGeometry( lineZ( points ) );
      if ( !newSink->addFeature( f, QgsFeatureSink::FastInsert ) )
        throw QgsProcessingException( writeFeatureError( newSink.get(), parameters, QStringLiteral( "NEW" ) ) );
    }
    outputs.insert( QStringLiteral( "NEW" ), newDestination );
  }
  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  if ( !reportPath.isEmpty() )
  {
    GeoStationProcessing::writeReport( report( s, QString::fromStdString( left.id ), QString::fromStdString( right.id ), static_cast<int>( map->featureCount() ) ), reportPath );
    outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  }
  feedback->pushInfo( QObject::tr( "%1 m confirmed, %2 m moved, %3 m not found, %4 m outside; %5 new roads." )
                      .arg( s.lengthM( geostation::RevisionStatus::Confirmed ), 0, 'f', 0 ).arg( s.lengthM( geostation::RevisionStatus::Moved ), 0, 'f', 0 )
                      .arg( s.lengthM( geostation::RevisionStatus::NotFound ), 0, 'f', 0 ).arg( s.lengthM( geostation::RevisionStatus::Outside ), 0, 'f', 0 )
                      .arg( s.newRoads.size() ) );
  return outputs;
}

} // namespace GeoStationProcessing
