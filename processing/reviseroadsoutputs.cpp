/***************************************************************************
  reviseroadsoutputs.cpp - the tables and REPORT of geostation:revise_roads
 ***************************************************************************/
#include "reviseroadsoutputs.h"

#include <map>
#include <utility>
#include <vector>

#include <QObject>

#include <qgsexception.h>

#include "io/featureschema.h"
#include "maproads.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

namespace
{
  double sigmaMax( const std::vector<Eigen::Vector3d> &sigmas )
  {
    double m = 0.0;
    for ( const Eigen::Vector3d &s : sigmas )
      m = std::max( m, s.maxCoeff() );
    return m;
  }
}

RevisedMapFields revisedMapFields( const QgsFields &mapFields )
{
  RevisedMapFields out;
  for ( int i = 0; i < mapFields.count(); ++i )
    if ( mapFields.at( i ).name().compare( QLatin1String( "fid" ), Qt::CaseInsensitive ) != 0 )
    {
      out.fields.append( mapFields.at( i ) );
      out.copied << i;
    }
  const std::vector<std::pair<const char *, QVariant::Type>> added { { fs::kSourceFid, QVariant::LongLong }, { fs::kRevision, QVariant::String }, { fs::kEvidence, QVariant::Double },
    { fs::kShiftM, QVariant::Double }, { fs::kSigmaMax, QVariant::Double }, { fs::kMapPart, QVariant::Int }, { fs::kMapFromM, QVariant::Double }, { fs::kMapToM, QVariant::Double } };
  for ( const auto &[name, type] : added )
    if ( out.fields.lookupField( QLatin1String( name ) ) >= 0 )
      throw QgsProcessingException( QObject::tr( "MAP has a field named %1, which the output adds: rename it first." ).arg( QLatin1String( name ) ) );
  for ( const auto &[name, type] : added )
    out.fields.append( QgsField( QLatin1String( name ), type ) );
  return out;
}

QgsFeature revisedMapFeature( const geostation::RevisedPiece &piece, const QgsFeature &source, int part, const RevisedMapFields &fields )
{
  QgsFeature f( fields.fields );
  QgsAttributes attributes;
  for ( const int i : fields.copied )
    attributes << source.attribute( i );
  attributes << source.id() << QString::fromStdString( geostation::revisionStatusName( piece.status ) ) << piece.evidence << piece.shiftM
             << ( piece.sigmaM.empty() ? QVariant() : QVariant( sigmaMax( piece.sigmaM ) ) ) << part << piece.fromM << piece.toM;
  f.setAttributes( attributes );
  if ( piece.status != geostation::RevisionStatus::InvalidGeometry )
    f.setGeometry( lineStringZ( piece.course ) );
  return f;
}

QgsFields revisionVertexFields()
{
  QgsFields fields;
  for ( const auto &[name, type] : std::vector<std::pair<const char *, QVariant::Type>> { { fs::kPiece, QVariant::Int }, { fs::kVertex, QVariant::Int }, { fs::kX, QVariant::Double },
        { fs::kY, QVariant::Double }, { fs::kZ, QVariant::Double }, { fs::kSx, QVariant::Double }, { fs::kSy, QVariant::Double }, { fs::kSz, QVariant::Double },
        { "height_from", QVariant::String }, { fs::kMapM, QVariant::Double } } )
    fields.append( QgsField( QString::fromLatin1( name ), type ) );
  return fields;
}

QList<QgsFeature> revisionVertexRows( const geostation::RevisedPiece &piece, int pieceNumber, const QgsFields &fields )
{
  QList<QgsFeature> rows;
  for ( size_t k = 0; k < piece.sigmaM.size() && k < piece.course.size(); ++k )
  {
    const bool stereo = k < piece.heightByStereo.size() && piece.heightByStereo[k];
    QgsFeature v( fields );
    v.setAttributes( QgsAttributes() << pieceNumber << static_cast<int>( k ) << piece.course[k].x() << piece.course[k].y() << piece.course[k].z()
                     << piece.sigmaM[k].x() << piece.sigmaM[k].y() << piece.sigmaM[k].z() << ( stereo ? QStringLiteral( "stereo" ) : QStringLiteral( "terrain" ) )
                     << ( k < piece.alongMapM.size() ? QVariant( piece.alongMapM[k] ) : QVariant() ) );
    rows << v;
  }
  return rows;
}

QgsFields newRoadFields()
{
  QgsFields fields;
  fields.append( QgsField( QLatin1String( fs::kLineId ), QVariant::Int ) );
  fields.append( QgsField( QLatin1String( fs::kMethod ), QVariant::String ) );
  fields.append( QgsField( QLatin1String( fs::kLengthM ), QVariant::Double ) );
  fields.append( QgsField( QLatin1String( fs::kSigmaMax ), QVariant::Double ) );
  return fields;
}

QgsFeature newRoadFeature( const geostation::NetworkLine &line, int lineId, const QgsFields &fields )
{
  std::vector<Eigen::Vector3d> points;
  for ( const geostation::NetworkVertex &v : line.vertices )
    points.push_back( v.point );
  QgsFeature f( fields );
  f.setAttributes( QgsAttributes() << lineId << QStringLiteral( "extracted" ) << line.lengthM() << line.sigmaMaxM() );
  f.setGeometry( lineStringZ( points ) );
  return f;
}

QJsonObject reviseRoadsReport( const geostation::MapRevisionSummary &s, const QString &leftId, const QString &rightId, long long mapFeatures )
{
  std::map<std::string, std::pair<int, double>> counts;
  for ( const geostation::RevisedPiece &p : s.pieces )
  {
    auto &c = counts[geostation::revisionStatusName( p.status )];
    ++c.first;
    c.second += p.lengthM();
  }
  QJsonObject byStatus;
  for ( const auto &[name, c] : counts )
    byStatus.insert( QString::fromStdString( name ), QJsonObject { { "pieces", c.first }, { "length_m", c.second } } );
  double newLength = 0.0;
  for ( const geostation::NetworkLine &l : s.newRoads )
    newLength += l.lengthM();
  const double decided = s.lengthM( geostation::RevisionStatus::Confirmed ) + s.lengthM( geostation::RevisionStatus::Moved ) +
                         s.lengthM( geostation::RevisionStatus::NotFound );
  return QJsonObject { { "left", leftId }, { "right", rightId }, { "map_features", static_cast<double>( mapFeatures ) }, { "samples", s.samples },
                       { "by_status", byStatus }, { "new", QJsonObject { { "lines", static_cast<int>( s.newRoads.size() ) }, { "length_m", newLength } } },
                       { "decided_by_the_map_m", decided }, { "found_by_extraction_m", newLength },
                       { "shift_max_m", s.shiftMaxM }, { "tolerance_m", s.toleranceM }, { "ground_pixel_m", s.groundPixelM },
                       { "mean_height_m", s.extraction.meanHeightM }, { "seconds", s.seconds },
                       { "extracted", !s.extraction.extraction.linesA.empty() || !s.newRoads.empty() } };
}

} // namespace GeoStationProcessing
