/***************************************************************************
  mergerevisionsalgorithm.cpp - geostation:merge_revisions
  -------------------------------------------------------------------------
  Parameters -> core/revision/revisionmerge -> outputs. Each input layer
  is one pair's OUTPUT of revise_roads, named by the layer's name (a
  file's base name), with that pair's VERTICES in the same place of the
  second list; every input is read before any output is made.
 ***************************************************************************/
#include "mergerevisionsalgorithm.h"

#include <map>
#include <memory>

#include <QJsonObject>

#include <qgsexception.h>
#include <qgsfeaturesink.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsvectorlayer.h>

#include "io/featureschema.h"
#include "maproads.h"
#include "processingblock.h"
#include "reviseroadsoutputs.h"
#include "revisionlayers.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

namespace
{
  QgsVectorLayer *lineLayer( QgsMapLayer *layer, bool lines )
  {
    QgsVectorLayer *vector = qobject_cast<QgsVectorLayer *>( layer );
    if ( !vector || ( lines && vector->geometryType() != QgsWkbTypes::LineGeometry ) )
      throw QgsProcessingException( lines ? QObject::tr( "%1 is not a line layer: every input is a pair's revised map (revise_roads' OUTPUT)." ).arg( layer->name() )
                                          : QObject::tr( "%1 is not a table: VERTICES are revise_roads' vertex tables." ).arg( layer->name() ) );
    return vector;
  }

  //! One merged row: the attributes of the row its first stretch came from (by name), the merge's own values over them.
  QgsFeature mergedRow( const geostation::MergedRevisionPiece &m, const QgsFeature &source, const QgsFields &fields, const std::pair<long long, int> &road )
  {
    QgsFeature f( fields );
    QgsAttributes attributes( fields.count() );
    for ( int i = 0; i < fields.count(); ++i )
      if ( source.fields().lookupField( fields.at( i ).name() ) >= 0 )
        attributes[i] = source.attribute( fields.at( i ).name() );
    double sigmaMax = 0.0;
    for ( const Eigen::Vector3d &s : m.piece.sigmaM )
      sigmaMax = std::max( sigmaMax, s.maxCoeff() );
    QStringList pairs;
    for ( const std::string &p : m.pairs )
      pairs << QString::fromStdString( p );
    const std::vector<std::pair<const char *, QVariant>> own { { fs::kSourceFid, road.first }, { fs::kMapPart, road.second },
      { fs::kRevision, QString::fromStdString( geostation::revisionStatusName( m.piece.status ) ) }, { fs::kEvidence, m.piece.evidence }, { fs::kShiftM, m.piece.shiftM },
      { fs::kSigmaMax, m.piece.sigmaM.empty() ? QVariant() : QVariant( sigmaMax ) }, { fs::kMapFromM, m.piece.fromM }, { fs::kMapToM, m.piece.toM },
      { fs::kPairs, pairs.join( ';' ) } };
    for ( const auto &[name, value] : own )
      attributes[fields.lookupField( QLatin1String( name ) )] = value;
    f.setAttributes( attributes );
    if ( m.piece.status != geostation::RevisionStatus::InvalidGeometry )
      f.setGeometry( lineStringZ( m.piece.course ) );
    return f;
  }
} // namespace

QString MergeRevisionsAlgorithm::name() const { return QStringLiteral( "merge_revisions" ); }
QString MergeRevisionsAlgorithm::displayName() const { return QObject::tr( "Merge the map revisions of overlapping pairs" ); }
QStringList MergeRevisionsAlgorithm::tags() const { return QObject::tr( "road,map,revision,merge,overlap,pairs,strip,block,batch" ).split( ',' ); }
QString MergeRevisionsAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString MergeRevisionsAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString MergeRevisionsAlgorithm::helpText() const
{
  return QObject::tr( "Makes one revised map of the revisions that Revise a road map against a stereo pair (revise_roads) made of one map "
                      "with overlapping pairs: each input layer (INPUTS) is one pair's OUTPUT, named by the layer's name, and VERTICES "
                      "holds the same pairs' vertex tables (revise_roads' VERTICES) in the same order: they carry each measured vertex's "
                      "sigma and place along the map line.\n\n"
                      "Each map line is cut wherever some pair's stretch begins or ends (map_from_m, map_to_m), and each stretch takes "
                      "the status of the pair that tells most about it: confirmed before moved before not_found before occluded before "
                      "outside; among equals the higher evidence, then the pair first by name. Stretches of one status that follow one "
                      "another are one feature again: its course is the chosen pairs' courses cut where the stretches end, its evidence "
                      "and shift their means weighted by length, pairs the pairs it came from (separated by ;). Pairs are taken in the "
                      "order of their names, so the result does not depend on the order of the inputs.\n\n"
                      "OUTPUT: the map's features as revise_roads writes them (LineStringZ in the inputs' CRS, revision, evidence, "
                      "shift_m, sigma_max, source_fid, map_part, map_from_m, map_to_m and the map's attributes) with pairs. "
                      "VERTICES_OUTPUT (optional): the measured courses' vertices as revise_roads' VERTICES. REPORT (optional): length along the map lines (map_length_m) and count per "
                      "status, the map length seen by more than one pair and the part of it where they disagree (confirmed, moved "
                      "or not found)." );
}

MergeRevisionsAlgorithm *MergeRevisionsAlgorithm::createInstance() const { return new MergeRevisionsAlgorithm(); }

void MergeRevisionsAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( new QgsProcessingParameterMultipleLayers( QStringLiteral( "INPUTS" ), QObject::tr( "Revised maps of the pairs" ), QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterMultipleLayers( QStringLiteral( "VERTICES" ), QObject::tr( "Vertex tables of the pairs (in the order of the revised maps)" ), QgsProcessing::TypeVector ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Merged revision" ), QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "VERTICES_OUTPUT" ), QObject::tr( "Vertices of the merged courses" ), QgsProcessing::TypeVector, QVariant(), true, false ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
}

QVariantMap MergeRevisionsAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  const QList<QgsMapLayer *> outputs = parameterAsLayerList( parameters, QStringLiteral( "INPUTS" ), context );
  const QList<QgsMapLayer *> tables = parameterAsLayerList( parameters, QStringLiteral( "VERTICES" ), context );
  if ( outputs.isEmpty() )
    throw QgsProcessingException( QObject::tr( "INPUTS holds no layer: give the revised maps of the pairs." ) );
  if ( tables.size() != outputs.size() )
    throw QgsProcessingException( QObject::tr( "VERTICES holds %1 tables for %2 revised maps: give one per pair, in the same order." ).arg( tables.size() ).arg( outputs.size() ) );
  MapRoadKeys keys;
  std::vector<RevisionLayer> layers;
  std::vector<geostation::PairRevision> revisions;
  QgsCoordinateReferenceSystem crs;
  for ( int i = 0; i < outputs.size(); ++i )
  {
    QgsVectorLayer *output = lineLayer( outputs[i], true );
    if ( !crs.isValid() )
      crs = output->crs();
    else if ( output->crs() != crs )
      throw QgsProcessingException( QObject::tr( "%1 is in %2, %3 in %4: the revisions of one block share its CRS." )
                                    .arg( outputs[0]->name(), crs.userFriendlyIdentifier(), output->name(), output->crs().userFriendlyIdentifier() ) );
    layers.push_back( readRevisionLayer( output, lineLayer( tables[i], false ), keys ) );
    revisions.push_back( layers.back().revision );
    if ( feedback->isCanceled() )
      throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );
  }
  const geostation::RevisionMergeSummary s = geostation::mergeRevisions( revisions ); // two pairs of one name: std::invalid_argument, one sentence

  // the first input's fields but a file's own feature id (pieces of several pairs would repeat it), then pairs
  QgsFields fields;
  for ( const QgsField &field : lineLayer( outputs[0], true )->fields() )
    if ( field.name().compare( QLatin1String( "fid" ), Qt::CaseInsensitive ) != 0 )
      fields.append( field );
  if ( fields.lookupField( QLatin1String( fs::kPairs ) ) >= 0 )
    throw QgsProcessingException( QObject::tr( "The revised maps have a field named pairs, which the output adds: rename it in the map first." ) );
  fields.append( QgsField( QLatin1String( fs::kPairs ), QVariant::String ) );
  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::LineStringZ, crs );
  for ( const geostation::MergedRevisionPiece &m : s.pieces )
  {
    QgsFeature f = mergedRow( m, layers[m.pairIndex].rows[static_cast<int>( m.pieceIndex )], fields, keys.keyOf( m.piece.road ) );
    sink.add( f );
  }
  QVariantMap result { { QStringLiteral( "OUTPUT" ), sink.close( true ) } };

  if ( outputRequested( parameters, QStringLiteral( "VERTICES_OUTPUT" ) ) )
  {
    const QgsFields vertexFields = revisionVertexFields();
    OutputSink vertexSink = openOutput( parameters, QStringLiteral( "VERTICES_OUTPUT" ), context, vertexFields, QgsWkbTypes::NoGeometry, QgsCoordinateReferenceSystem() );
    for ( size_t i = 0; i < s.pieces.size(); ++i )
    {
      QgsFeatureList rows = revisionVertexRows( s.pieces[i].piece, static_cast<int>( i + 1 ), vertexFields );
      vertexSink.add( rows );
    }
    result.insert( QStringLiteral( "VERTICES_OUTPUT" ), vertexSink.destination() );
  }

  std::map<std::string, std::pair<int, double>> byStatus;
  for ( const geostation::MergedRevisionPiece &m : s.pieces )
  {
    auto &c = byStatus[geostation::revisionStatusName( m.piece.status )];
    ++c.first;
    c.second += m.piece.toM - m.piece.fromM;
  }
  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  if ( !reportPath.isEmpty() )
  {
    QJsonObject statuses;
    for ( const auto &[name, c] : byStatus )
      statuses.insert( QString::fromStdString( name ), QJsonObject { { "pieces", c.first }, { "map_length_m", c.second } } );
    writeReport( QJsonObject { { "pairs", static_cast<int>( revisions.size() ) }, { "pieces_in", s.piecesIn }, { "pieces_out", static_cast<int>( s.pieces.size() ) },
                               { "by_status", statuses }, { "seen_twice_m", s.seenTwiceM }, { "disagreed_m", s.disagreedM } },
                 reportPath );
    result.insert( QStringLiteral( "REPORT" ), reportPath );
  }
  feedback->pushInfo( QObject::tr( "%1 pieces of %2 pairs merged into %3: %4 m confirmed, %5 m moved, %6 m not found; %7 m seen by more than one pair, %8 m of it with different statuses." )
                      .arg( s.piecesIn ).arg( revisions.size() ).arg( s.pieces.size() ).arg( s.lengthM( geostation::RevisionStatus::Confirmed ), 0, 'f', 0 )
                      .arg( s.lengthM( geostation::RevisionStatus::Moved ), 0, 'f', 0 ).arg( s.lengthM( geostation::RevisionStatus::NotFound ), 0, 'f', 0 )
                      .arg( s.seenTwiceM, 0, 'f', 0 ).arg( s.disagreedM, 0, 'f', 0 ) );
  return result;
}

} // namespace GeoStationProcessing
