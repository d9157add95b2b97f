/***************************************************************************
  revisionlayers.cpp - revise_roads' OUTPUT and VERTICES read back for core
 ***************************************************************************/
#include "revisionlayers.h"

#include <cmath>

#include <QObject>

#include <qgsexception.h>
#include <qgsfeatureiterator.h>
#include <qgsvectorlayer.h>

#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace GeoStationProcessing
{

size_t MapRoadKeys::indexOf( long long sourceFid, int part )
{
  const auto [it, added] = mIndex.emplace( std::make_pair( sourceFid, part ), mKeys.size() );
  if ( added )
    mKeys.emplace_back( sourceFid, part );
  return it->second;
}

namespace
{
  struct MeasuredVertex
  {
    Eigen::Vector3d point, sigma;
    bool stereo = false;
    double alongMapM = 0.0;
  };

  //! The vertex table's rows by piece (the OUTPUT row, from 1), each in vertex order.
  std::map<int, std::map<int, MeasuredVertex>> readVertices( QgsVectorLayer *vertices )
  {
    std::map<int, std::map<int, MeasuredVertex>> out;
    const QgsFields fields = vertices->fields();
    for ( const char *name : { fs::kPiece, fs::kVertex, fs::kX, fs::kY, fs::kZ, fs::kSx, fs::kSy, fs::kSz, fs::kMapM } )
      if ( fields.lookupField( QLatin1String( name ) ) < 0 )
        throw QgsProcessingException( QObject::tr( "%1 is not a vertex table of revise_roads (it has no field %2): give the pairs' VERTICES as revise_roads wrote them." )
                                      .arg( vertices->name(), QLatin1String( name ) ) );
    QgsFeature f;
    QgsFeatureIterator it = vertices->getFeatures();
    while ( it.nextFeature( f ) )
    {
      const auto number = [&]( const char *name ) { return f.attribute( QLatin1String( name ) ).toDouble(); };
      MeasuredVertex v;
      v.point = Eigen::Vector3d( number( fs::kX ), number( fs::kY ), number( fs::kZ ) );
      v.sigma = Eigen::Vector3d( number( fs::kSx ), number( fs::kSy ), number( fs::kSz ) );
      v.stereo = f.attribute( QStringLiteral( "height_from" ) ).toString() == QLatin1String( "stereo" );
      v.alongMapM = number( fs::kMapM );
      if ( !v.point.allFinite() || !v.sigma.allFinite() || !std::isfinite( v.alongMapM ) )
        throw QgsProcessingException( QObject::tr( "A row of %1 (piece %2) has an empty coordinate, sigma or map_m: the table was changed after revise_roads wrote it." )
                                      .arg( vertices->name() ).arg( f.attribute( QLatin1String( fs::kPiece ) ).toInt() ) );
      out[f.attribute( QLatin1String( fs::kPiece ) ).toInt()][f.attribute( QLatin1String( fs::kVertex ) ).toInt()] = v;
    }
    return out;
  }

  //! The map's course of a row (not measured): its vertices, placed along the map line from map_from_m on.
  void mapCourse( const QgsGeometry &g, geostation::RevisedPiece &piece )
  {
    for ( auto v = g.vertices_begin(); v != g.vertices_end(); ++v )
    {
      const Eigen::Vector3d p( ( *v ).x(), ( *v ).y(), std::isfinite( ( *v ).z() ) ? ( *v ).z() : 0.0 );
      piece.alongMapM.push_back( piece.course.empty() ? piece.fromM : piece.alongMapM.back() + ( p - piece.course.back() ).head<2>().norm() );
      piece.course.push_back( p );
    }
  }
} // namespace

RevisionLayer readRevisionLayer( QgsVectorLayer *output, QgsVectorLayer *vertices, MapRoadKeys &keys )
{
  const QgsFields fields = output->fields();
  for ( const char *name : { fs::kSourceFid, fs::kRevision, fs::kEvidence, fs::kShiftM, fs::kSigmaMax, fs::kMapPart, fs::kMapFromM, fs::kMapToM } )
    if ( fields.lookupField( QLatin1String( name ) ) < 0 )
      throw QgsProcessingException( QObject::tr( "%1 is not an OUTPUT of revise_roads as this version writes it (it has no field %2): revise the pair again." )
                                    .arg( output->name(), QLatin1String( name ) ) );
  const std::map<int, std::map<int, MeasuredVertex>> measured = readVertices( vertices );
  RevisionLayer layer;
  layer.revision.pair = output->name().toStdString();
  QgsFeature f;
  QgsFeatureIterator it = output->getFeatures();
  for ( int row = 1; it.nextFeature( f ); ++row )
  {
    const QString name = f.attribute( QLatin1String( fs::kRevision ) ).toString();
    const std::optional<geostation::RevisionStatus> status = geostation::revisionStatusFromName( name.toStdString() );
    if ( !status )
      throw QgsProcessingException( QObject::tr( "Row %1 of %2 has the revision '%3', which revise_roads does not write." ).arg( row ).arg( output->name(), name ) );
    geostation::RevisedPiece piece;
    piece.road = keys.indexOf( f.attribute( QLatin1String( fs::kSourceFid ) ).toLongLong(), f.attribute( QLatin1String( fs::kMapPart ) ).toInt() );
    piece.status = *status;
    piece.evidence = f.attribute( QLatin1String( fs::kEvidence ) ).toDouble();
    piece.shiftM = f.attribute( QLatin1String( fs::kShiftM ) ).toDouble();
    piece.fromM = f.attribute( QLatin1String( fs::kMapFromM ) ).toDouble();
    piece.toM = f.attribute( QLatin1String( fs::kMapToM ) ).toDouble();
    if ( f.attribute( QLatin1String( fs::kSigmaMax ) ).isNull() )
    {
      if ( f.hasGeometry() )
        mapCourse( f.geometry(), piece );
    }
    else
    {
      const auto found = measured.find( row );
      if ( found == measured.end() )
        throw QgsProcessingException( QObject::tr( "Row %1 of %2 was measured, but %3 has no vertex of it: give each pair's own VERTICES, in the order of INPUTS." )
                                      .arg( row ).arg( output->name(), vertices->name() ) );
      for ( const auto &[index, v] : found->second )
      {
        piece.course.push_back( v.point );
        piece.sigmaM.push_back( v.sigma );
        piece.heightByStereo.push_back( v.stereo );
        piece.alongMapM.push_back( v.alongMapM );
      }
    }
    layer.revision.pieces.push_back( piece );
    layer.rows << f;
  }
  return layer;
}

} // namespace GeoStationProcessing
