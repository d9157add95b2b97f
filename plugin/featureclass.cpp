/***************************************************************************
  featureclass.cpp
 ***************************************************************************/
#include "featureclass.h"

#include "io/featureschema.h"

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QRegularExpression>
#include <QSet>

QString GeoStationFeatureClass::geometryName( Geometry geometry )
{
  switch ( geometry )
  {
    case Geometry::Point:
      return QStringLiteral( "point" );
    case Geometry::Line:
      return QStringLiteral( "line" );
    case Geometry::Polygon:
      return QStringLiteral( "polygon" );
  }
  return QStringLiteral( "point" );
}

bool GeoStationFeatureClass::geometryFromName( const QString &name, Geometry &geometry )
{
  const QString n = name.trimmed().toLower();
  if ( n == QLatin1String( "point" ) )
    geometry = Geometry::Point;
  else if ( n == QLatin1String( "line" ) || n == QLatin1String( "linestring" ) )
    geometry = Geometry::Line;
  else if ( n == QLatin1String( "polygon" ) )
    geometry = Geometry::Polygon;
  else
    return false;
  return true;
}

QString GeoStationFeatureClass::layerName() const
{
  QString n = name.trimmed().toLower();
  n.replace( QRegularExpression( QStringLiteral( "[^a-z0-9_]" ) ), QStringLiteral( "_" ) );
  if ( n.isEmpty() || n.at( 0 ).isDigit() )
    n.prepend( QStringLiteral( "c_" ) );
  return n;
}

QStringList GeoStationFeatureClass::reservedFieldNames()
{
  QStringList names { QStringLiteral( "fid" ) };
  for ( const char *name : geostation::featureschema::kFeatureFields )
    names << QString::fromLatin1( name );
  return names;
}

QString GeoStationFeatureClass::toJson( const QList<GeoStationFeatureClass> &classes )
{
  QJsonArray array;
  for ( const GeoStationFeatureClass &c : classes )
  {
    QJsonObject o;
    o.insert( QStringLiteral( "name" ), c.name );
    o.insert( QStringLiteral( "geometry" ), geometryName( c.geometry ) );
    o.insert( QStringLiteral( "attributes" ), QJsonObject::fromVariantMap( c.attributes ) );
    array.append( o );
  }
  return QString::fromUtf8( QJsonDocument( array ).toJson( QJsonDocument::Compact ) );
}

bool GeoStationFeatureClass::fromJson( const QString &json, QList<GeoStationFeatureClass> &classes, QString *error )
{
  QJsonParseError parseError;
  const QJsonDocument doc = QJsonDocument::fromJson( json.toUtf8(), &parseError );
  if ( !doc.isArray() )
  {
    if ( error )
      *error = QObject::tr( "The feature classes are not a JSON array (%1)." ).arg( parseError.errorString() );
    return false;
  }
  QList<GeoStationFeatureClass> parsed;
  QSet<QString> layerNames;
  const QStringList reserved = reservedFieldNames();
  const QJsonArray array = doc.array();
  for ( int i = 0; i < array.size(); ++i )
  {
    const QJsonObject o = array.at( i ).toObject();
    GeoStationFeatureClass c;
    c.name = o.value( QStringLiteral( "name" ) ).toString().trimmed();
    const auto fail = [&]( const QString &problem )
    {
      if ( error )
        *error = QObject::tr( "Feature class %1 (%2): %3." ).arg( i + 1 ).arg( c.name.isEmpty() ? QObject::tr( "no name" ) : c.name, problem );
      return false;
    };
    if ( c.name.isEmpty() )
      return fail( QObject::tr( "a class needs a name" ) );
    if ( !geometryFromName( o.value( QStringLiteral( "geometry" ) ).toString(), c.geometry ) )
      return fail( QObject::tr( "the geometry must be point, line or polygon" ) );
    c.attributes = o.value( QStringLiteral( "attributes" ) ).toObject().toVariantMap();
    for ( auto it = c.attributes.constBegin(); it != c.attributes.constEnd(); ++it )
      if ( reserved.contains( it.key().toLower() ) )
        return fail( QObject::tr( "the attribute %1 is a measurement field" ).arg( it.key() ) );
    if ( layerNames.contains( c.layerName() ) )
      return fail( QObject::tr( "another class has the same layer name %1" ).arg( c.layerName() ) );
    layerNames.insert( c.layerName() );
    parsed << c;
  }
  classes = parsed;
  return true;
}

// ---- model ----

