/***************************************************************************
  featureclass.cpp
 ***************************************************************************/
#include "featureclass.h"

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
  return { QStringLiteral( "fid" ), QStringLiteral( "class" ), QStringLiteral( "station" ), QStringLiteral( "acquired" ), QStringLiteral( "measured" ),
           QStringLiteral( "n_images" ), QStringLiteral( "sigma_x" ), QStringLiteral( "sigma_y" ), QStringLiteral( "sigma_z" ),
           QStringLiteral( "method" ), QStringLiteral( "measurement_id" ) };
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

GeoStationFeatureClassModel::GeoStationFeatureClassModel( QObject *parent )
  : QAbstractTableModel( parent )
{
}

void GeoStationFeatureClassModel::setClasses( const QList<GeoStationFeatureClass> &classes )
{
  beginResetModel();
  mClasses = classes;
  endResetModel();
}

int GeoStationFeatureClassModel::addClass( GeoStationFeatureClass::Geometry geometry )
{
  GeoStationFeatureClass c;
  c.geometry = geometry;
  const QString base = GeoStationFeatureClass::geometryName( geometry );
  for ( int k = 1;; ++k )
  {
    c.name = QStringLiteral( "%1_%2" ).arg( base ).arg( k );
    bool taken = false;
    for ( const GeoStationFeatureClass &other : std::as_const( mClasses ) )
      taken = taken || other.layerName() == c.layerName();
    if ( !taken )
      break;
  }
  beginInsertRows( QModelIndex(), mClasses.size(), mClasses.size() );
  mClasses << c;
  endInsertRows();
  return mClasses.size() - 1;
}

void GeoStationFeatureClassModel::removeClassAt( int row )
{
  if ( row < 0 || row >= mClasses.size() )
    return;
  beginRemoveRows( QModelIndex(), row, row );
  mClasses.removeAt( row );
  endRemoveRows();
}

bool GeoStationFeatureClassModel::validate( QString *error ) const
{
  QList<GeoStationFeatureClass> check;
  return GeoStationFeatureClass::fromJson( GeoStationFeatureClass::toJson( mClasses ), check, error );
}

QString GeoStationFeatureClassModel::attributesText( const QVariantMap &attributes )
{
  QStringList parts;
  for ( auto it = attributes.constBegin(); it != attributes.constEnd(); ++it )
    parts << QStringLiteral( "%1=%2" ).arg( it.key(), it.value().toString() );
  return parts.join( QLatin1String( "; " ) );
}

bool GeoStationFeatureClassModel::attributesFromText( const QString &text, QVariantMap &attributes, QString *error )
{
  QVariantMap parsed;
  for ( const QString &part : text.split( ';', Qt::SkipEmptyParts ) )
  {
    const int eq = part.indexOf( '=' );
    const QString key = part.left( eq ).trimmed();
    if ( eq <= 0 || key.isEmpty() || !QRegularExpression( QStringLiteral( "^[A-Za-z_][A-Za-z0-9_]*$" ) ).match( key ).hasMatch() )
    {
      if ( error )
        *error = QObject::tr( "“%1” is not key=value with a field name as key." ).arg( part.trimmed() );
      return false;
    }
    parsed.insert( key, part.mid( eq + 1 ).trimmed() );
  }
  attributes = parsed;
  return true;
}

int GeoStationFeatureClassModel::rowCount( const QModelIndex &parent ) const
{
  return parent.isValid() ? 0 : mClasses.size();
}

int GeoStationFeatureClassModel::columnCount( const QModelIndex &parent ) const
{
  return parent.isValid() ? 0 : ColumnCount;
}

QVariant GeoStationFeatureClassModel::data( const QModelIndex &index, int role ) const
{
  if ( !index.isValid() || index.row() >= mClasses.size() || ( role != Qt::DisplayRole && role != Qt::EditRole ) )
    return QVariant();
  const GeoStationFeatureClass &c = mClasses.at( index.row() );
  switch ( index.column() )
  {
    case Name:
      return c.name;
    case GeometryColumn:
      return GeoStationFeatureClass::geometryName( c.geometry );
    case Attributes:
      return attributesText( c.attributes );
  }
  return QVariant();
}

bool GeoStationFeatureClassModel::setData( const QModelIndex &index, const QVariant &value, int role )
{
  if ( !index.isValid() || index.row() >= mClasses.size() || role != Qt::EditRole )
    return false;
  GeoStationFeatureClass &c = mClasses[index.row()];
  switch ( index.column() )
  {
    case Name:
      if ( value.toString().trimmed().isEmpty() )
        return false;
      c.name = value.toString().trimmed();
      break;
    case GeometryColumn:
      if ( !GeoStationFeatureClass::geometryFromName( value.toString(), c.geometry ) )
        return false;
      break;
    case Attributes:
      if ( !attributesFromText( value.toString(), c.attributes, nullptr ) )
        return false;
      break;
    default:
      return false;
  }
  emit dataChanged( index, index );
  return true;
}

QVariant GeoStationFeatureClassModel::headerData( int section, Qt::Orientation orientation, int role ) const
{
  if ( orientation != Qt::Horizontal || role != Qt::DisplayRole )
    return QVariant();
  switch ( section )
  {
    case Name:
      return tr( "Class" );
    case GeometryColumn:
      return tr( "Geometry" );
    case Attributes:
      return tr( "Default attributes" );
  }
  return QVariant();
}

Qt::ItemFlags GeoStationFeatureClassModel::flags( const QModelIndex &index ) const
{
  return QAbstractTableModel::flags( index ) | Qt::ItemIsEditable;
}
