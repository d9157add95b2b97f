/***************************************************************************
  featureclassmodel.cpp - the table model of the feature classes
 ***************************************************************************/
#include "featureclassmodel.h"

#include <QRegularExpression>

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
  return parent.isValid() ? 0 : kColumnCount;
}

QVariant GeoStationFeatureClassModel::data( const QModelIndex &index, int role ) const
{
  if ( !index.isValid() || index.row() >= mClasses.size() || ( role != Qt::DisplayRole && role != Qt::EditRole ) )
    return QVariant();
  const GeoStationFeatureClass &c = mClasses.at( index.row() );
  switch ( static_cast<Column>( index.column() ) )
  {
    case Column::Name:
      return c.name;
    case Column::Geometry:
      return GeoStationFeatureClass::geometryName( c.geometry );
    case Column::Attributes:
      return attributesText( c.attributes );
    case Column::Count:
      break;
  }
  return QVariant();
}

bool GeoStationFeatureClassModel::setData( const QModelIndex &index, const QVariant &value, int role )
{
  if ( !index.isValid() || index.row() >= mClasses.size() || role != Qt::EditRole )
    return false;
  GeoStationFeatureClass &c = mClasses[index.row()];
  switch ( static_cast<Column>( index.column() ) )
  {
    case Column::Name:
      if ( value.toString().trimmed().isEmpty() )
        return false;
      c.name = value.toString().trimmed();
      break;
    case Column::Geometry:
      if ( !GeoStationFeatureClass::geometryFromName( value.toString(), c.geometry ) )
        return false;
      break;
    case Column::Attributes:
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
  switch ( static_cast<Column>( section ) )
  {
    case Column::Name:
      return tr( "Class" );
    case Column::Geometry:
      return tr( "Geometry" );
    case Column::Attributes:
      return tr( "Default attributes" );
    case Column::Count:
      break;
  }
  return QVariant();
}

Qt::ItemFlags GeoStationFeatureClassModel::flags( const QModelIndex &index ) const
{
  return QAbstractTableModel::flags( index ) | Qt::ItemIsEditable;
}
