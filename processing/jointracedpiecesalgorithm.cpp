/***************************************************************************
  jointracedpiecesalgorithm.cpp - geostation:join_traced_pieces
  -------------------------------------------------------------------------
  Parameters -> core/tracing/piecejoin -> outputs. Every piece is read
  before any output is made.
 ***************************************************************************/
#include "jointracedpiecesalgorithm.h"

#include <cmath>
#include <memory>

#include <QJsonArray>
#include <QJsonObject>

#include <qgsexception.h>
#include <qgsfeatureiterator.h>
#include <qgsfeaturesink.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>

#include "maproads.h"
#include "processingblock.h"
#include "tracing/piecejoin.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

QString JoinTracedPiecesAlgorithm::name() const { return QStringLiteral( "join_traced_pieces" ); }
QString JoinTracedPiecesAlgorithm::displayName() const { return QObject::tr( "Join lines traced in pieces" ); }
QStringList JoinTracedPiecesAlgorithm::tags() const { return QObject::tr( "road,line,trace,pieces,seeds,join,merge,batch,run" ).split( ',' ); }
QString JoinTracedPiecesAlgorithm::group() const { return QObject::tr( "Image processing" ); }
QString JoinTracedPiecesAlgorithm::groupId() const { return QStringLiteral( "imageprocessing" ); }

QString JoinTracedPiecesAlgorithm::helpText() const
{
  return QObject::tr( "Joins the pieces of long lines traced from several seeds (Trace road lines, one run per seed) "
                      "into one line per line id.\n\n"
                      "INPUT: the pieces, lines with the fields line_id (the line a piece belongs to) and piece (its seed's place "
                      "along the line: 1, 2, ...), and optionally sigma_max (m) and seed_id (to name it in the report). "
                      "Where two pieces run together within 1 cm for 5 vertices or more (a trace from a seed settles onto the one that "
                      "came through), the earlier piece is kept up to the last place they do and the next goes on from there; "
                      "elsewhere each piece runs up to where the next one starts. "
                      "Where two pieces never run together, each vertex of the earlier one is compared with the later piece: one farther off than "
                      "Sigma factor times their combined sigma_max is reported, as is a piece that ends before the next one starts "
                      "(joined straight across the gap).\n\n"
                      "OUTPUT: LineStringZ with line_id, pieces, length_m and sigma_max. REPORT (optional): the lines and every "
                      "disagreement (line, pieces, the worst distance, what was allowed, the overlap, gap or not)." );
}

JoinTracedPiecesAlgorithm *JoinTracedPiecesAlgorithm::createInstance() const { return new JoinTracedPiecesAlgorithm(); }

void JoinTracedPiecesAlgorithm::initAlgorithm( const QVariantMap & )
{
  addParameter( new QgsProcessingParameterFeatureSource( QStringLiteral( "INPUT" ), QObject::tr( "Traced pieces (line_id, piece)" ), QList<int>() << QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterNumber( QStringLiteral( "SIGMA_FACTOR" ), QObject::tr( "Sigma factor" ), QgsProcessingParameterNumber::Double, 3.0, false, 0.1, 100.0 ) );
  addParameter( new QgsProcessingParameterFeatureSink( QStringLiteral( "OUTPUT" ), QObject::tr( "Joined lines" ), QgsProcessing::TypeVectorLine ) );
  addParameter( new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT" ), QObject::tr( "Report" ), QObject::tr( "JSON (*.json)" ), QVariant(), true, false ) );
}

QVariantMap JoinTracedPiecesAlgorithm::processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingFeatureSource> source( parameterAsSource( parameters, QStringLiteral( "INPUT" ), context ) );
  if ( !source )
    throw QgsProcessingException( invalidSourceError( parameters, QStringLiteral( "INPUT" ) ) );
  const int lineField = source->fields().lookupField( QLatin1String( fs::kLineId ) ), pieceField = source->fields().lookupField( QStringLiteral( "piece" ) );
  if ( lineField < 0 || pieceField < 0 )
    throw QgsProcessingException( QObject::tr( "INPUT needs the fields line_id and piece (the seed's place along its line)." ) );
  const int sigmaField = source->fields().lookupField( QLatin1String( fs::kSigmaMax ) ), seedField = source->fields().lookupField( QLatin1String( fs::kSeedId ) );
  std::vector<geostation::TracedPiece> pieces;
  QgsFeature f;
  QgsFeatureIterator it = source->getFeatures();
  while ( it.nextFeature( f ) )
  {
    if ( feedback->isCanceled() )
      throw QgsProcessingException( QObject::tr( "Cancelled: nothing was written." ) );
    bool ok = false;
    geostation::TracedPiece piece;
    piece.lineId = f.attribute( lineField ).toString().toStdString();
    piece.order = f.attribute( pieceField ).toInt( &ok );
    if ( !ok || f.attribute( lineField ).isNull() )
      throw QgsProcessingException( QObject::tr( "Feature %1 has no line_id or no whole number in piece." ).arg( f.id() ) );
    const double sigma = sigmaField >= 0 ? f.attribute( sigmaField ).toDouble() : 0.0;
    piece.sigmaM = std::isfinite( sigma ) && sigma > 0.0 ? sigma : 0.0;
    piece.name = seedField >= 0 && !f.attribute( seedField ).isNull() ? f.attribute( seedField ).toString().toStdString() : piece.lineId + "#" + std::to_string( piece.order );
    const QgsGeometry g = f.geometry();
    if ( !g.isNull() )
      for ( auto v = g.vertices_begin(); v != g.vertices_end(); ++v )
        piece.points.emplace_back( ( *v ).x(), ( *v ).y(), std::isfinite( ( *v ).z() ) ? ( *v ).z() : 0.0 );
    pieces.push_back( piece );
  }
  geostation::PieceJoinOptions options;
  options.sigmaFactor = parameterAsDouble( parameters, QStringLiteral( "SIGMA_FACTOR" ), context );
  const geostation::PieceJoinSummary s = geostation::joinTracedPieces( pieces, options ); // two pieces in one place: one sentence

  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kLineId ), QVariant::String ) );
  fields.append( QgsField( QStringLiteral( "pieces" ), QVariant::Int ) );
  fields.append( QgsField( QLatin1String( fs::kLengthM ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kSigmaMax ), QVariant::Double ) );
  OutputSink sink = openOutput( parameters, QStringLiteral( "OUTPUT" ), context, fields, QgsWkbTypes::LineStringZ, source->sourceCrs() );
  QJsonArray lines;
  for ( const geostation::JoinedLine &line : s.lines )
  {
    double length = 0.0;
    for ( size_t i = 1; i < line.points.size(); ++i )
      length += ( line.points[i] - line.points[i - 1] ).norm();
    QgsFeature out( fields );
    out.setAttributes( QgsAttributes() << QString::fromStdString( line.lineId ) << line.pieces << length << line.sigmaM );
    out.setGeometry( lineStringZ( line.points ) );
    sink.add( out );
    lines.append( QJsonObject { { "line_id", QString::fromStdString( line.lineId ) }, { "pieces", line.pieces }, { "length_m", length } } );
  }
  QVariantMap outputs { { QStringLiteral( "OUTPUT" ), sink.destination() } };
  QJsonArray disagreements;
  for ( const geostation::PieceDisagreement &d : s.disagreements )
  {
    disagreements.append( QJsonObject { { "line_id", QString::fromStdString( d.lineId ) }, { "first", QString::fromStdString( d.first ) },
                                        { "second", QString::fromStdString( d.second ) }, { "worst_m", d.worstM }, { "allowed_m", d.allowedM },
                                        { "overlap_m", d.overlapM }, { "gap", d.gap } } );
    feedback->pushWarning( d.gap ? QObject::tr( "Line %1: %2 ends %3 m before %4 starts." ).arg( QString::fromStdString( d.lineId ), QString::fromStdString( d.first ) ).arg( d.worstM, 0, 'f', 2 ).arg( QString::fromStdString( d.second ) )
                           : QObject::tr( "Line %1: %2 and %3 are %4 m apart where they overlap (%5 m allowed)." ).arg( QString::fromStdString( d.lineId ), QString::fromStdString( d.first ), QString::fromStdString( d.second ) ).arg( d.worstM, 0, 'f', 3 ).arg( d.allowedM, 0, 'f', 3 ) );
  }
  const QString reportPath = parameterAsFileOutput( parameters, QStringLiteral( "REPORT" ), context );
  if ( !reportPath.isEmpty() )
  {
    GeoStationProcessing::writeReport( QJsonObject { { "pieces", static_cast<int>( pieces.size() ) }, { "lines", lines }, { "disagreements", disagreements } }, reportPath );
    outputs.insert( QStringLiteral( "REPORT" ), reportPath );
  }
  feedback->pushInfo( QObject::tr( "%1 pieces joined into %2 lines; %3 places where pieces disagree or do not meet." ).arg( pieces.size() ).arg( s.lines.size() ).arg( s.disagreements.size() ) );
  return outputs;
}

} // namespace GeoStationProcessing
