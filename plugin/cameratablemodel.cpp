/***************************************************************************
  cameratablemodel.cpp - the cameras of a block as a table
 ***************************************************************************/
#include "cameratablemodel.h"

#include "io/block.h"

GeoStationCameraTableModel::GeoStationCameraTableModel( QObject *parent )
  : QAbstractTableModel( parent )
{}

void GeoStationCameraTableModel::setBlock( const geostation::Block *block )
{
  beginResetModel();
  mBlock = block;
  endResetModel();
}

int GeoStationCameraTableModel::rowCount( const QModelIndex &parent ) const
{
  return parent.isValid() || !mBlock ? 0 : static_cast<int>( mBlock->cameras.size() );
}

int GeoStationCameraTableModel::columnCount( const QModelIndex &parent ) const
{
  return parent.isValid() ? 0 : ColumnCount;
}

QVariant GeoStationCameraTableModel::data( const QModelIndex &index, int role ) const
{
  if ( !mBlock || !index.isValid() || index.row() >= rowCount() )
    return QVariant();
  const geostation::Camera &camera = mBlock->cameras[static_cast<size_t>( index.row() )];

  if ( role == Qt::TextAlignmentRole )
    return index.column() == ColumnId || index.column() == ColumnModel ? QVariant( Qt::AlignLeft | Qt::AlignVCenter ) : QVariant( Qt::AlignRight | Qt::AlignVCenter );
  if ( role != Qt::DisplayRole && role != Qt::EditRole && role != Qt::ToolTipRole )
    return QVariant();

  const bool display = role != Qt::EditRole;
  const auto number = [display]( double value, int decimals ) { return display ? QVariant( QString::number( value, 'f', decimals ) ) : QVariant( value ); };
  const auto coefficient = [display, &camera]( double value ) -> QVariant
  {
    if ( camera.distortion.model == geostation::DistortionModel::None )
      return QVariant();
    return display ? QVariant( QString::number( value, 'g', 6 ) ) : QVariant( value );
  };

  switch ( index.column() )
  {
    case ColumnId:
      return QString::fromStdString( camera.id );
    case ColumnSize:
      return QStringLiteral( "%1 × %2" ).arg( camera.width ).arg( camera.height );
    case ColumnF:
      return number( camera.f, 3 );
    case ColumnAspect:
      return number( camera.aspect, 6 );
    case ColumnCx:
      return number( camera.cx, 3 );
    case ColumnCy:
      return number( camera.cy, 3 );
    case ColumnPixelSize:
      return camera.pixelSizeMm ? number( *camera.pixelSizeMm, 6 ) : QVariant();
    case ColumnModel:
      return QString::fromStdString( geostation::distortionModelName( camera.distortion.model ) );
    case ColumnK1:
      return coefficient( camera.distortion.k1() );
    case ColumnK2:
      return coefficient( camera.distortion.k2() );
    case ColumnP1:
      return coefficient( camera.distortion.p1() );
    case ColumnP2:
      return coefficient( camera.distortion.p2() );
    case ColumnK3:
      return coefficient( camera.distortion.k3() );
    case ColumnImages:
    {
      int count = 0;
      for ( const geostation::BlockImage &image : mBlock->images )
        count += image.cameraId == camera.id ? 1 : 0;
      return count;
    }
    default:
      return QVariant();
  }
}

QVariant GeoStationCameraTableModel::headerData( int section, Qt::Orientation orientation, int role ) const
{
  if ( orientation != Qt::Horizontal || role != Qt::DisplayRole )
    return QAbstractTableModel::headerData( section, orientation, role );
  switch ( section )
  {
    case ColumnId:
      return tr( "Camera" );
    case ColumnSize:
      return tr( "Size [px]" );
    case ColumnF:
      return tr( "f [px]" );
    case ColumnAspect:
      return tr( "Aspect" );
    case ColumnCx:
      return tr( "cx [px]" );
    case ColumnCy:
      return tr( "cy [px]" );
    case ColumnPixelSize:
      return tr( "Pixel [mm]" );
    case ColumnModel:
      return tr( "Distortion" );
    case ColumnK1:
      return QStringLiteral( "k1" );
    case ColumnK2:
      return QStringLiteral( "k2" );
    case ColumnP1:
      return QStringLiteral( "p1" );
    case ColumnP2:
      return QStringLiteral( "p2" );
    case ColumnK3:
      return QStringLiteral( "k3" );
    case ColumnImages:
      return tr( "Images" );
    default:
      return QVariant();
  }
}
