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
  return parent.isValid() ? 0 : kColumnCount;
}

QVariant GeoStationCameraTableModel::data( const QModelIndex &index, int role ) const
{
  if ( !mBlock || !index.isValid() || index.row() >= rowCount() )
    return QVariant();
  const geostation::Camera &camera = mBlock->cameras[static_cast<size_t>( index.row() )];

  if ( role == Qt::TextAlignmentRole )
    return index.column() == static_cast<int>( Column::Id ) || index.column() == static_cast<int>( Column::Model ) ? QVariant( Qt::AlignLeft | Qt::AlignVCenter ) : QVariant( Qt::AlignRight | Qt::AlignVCenter );
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

  switch ( static_cast<Column>( index.column() ) )
  {
    case Column::Id:
      return QString::fromStdString( camera.id );
    case Column::Size:
      return QStringLiteral( "%1 × %2" ).arg( camera.width ).arg( camera.height );
    case Column::F:
      return number( camera.f, 3 );
    case Column::Aspect:
      return number( camera.aspect, 6 );
    case Column::Cx:
      return number( camera.cx, 3 );
    case Column::Cy:
      return number( camera.cy, 3 );
    case Column::PixelSize:
      return camera.pixelSizeMm ? number( *camera.pixelSizeMm, 6 ) : QVariant();
    case Column::Model:
      return QString::fromStdString( geostation::distortionModelName( camera.distortion.model ) );
    case Column::K1:
      return coefficient( camera.distortion.k1() );
    case Column::K2:
      return coefficient( camera.distortion.k2() );
    case Column::P1:
      return coefficient( camera.distortion.p1() );
    case Column::P2:
      return coefficient( camera.distortion.p2() );
    case Column::K3:
      return coefficient( camera.distortion.k3() );
    case Column::Images:
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
  switch ( static_cast<Column>( section ) )
  {
    case Column::Id:
      return tr( "Camera" );
    case Column::Size:
      return tr( "Size [px]" );
    case Column::F:
      return tr( "f [px]" );
    case Column::Aspect:
      return tr( "Aspect" );
    case Column::Cx:
      return tr( "cx [px]" );
    case Column::Cy:
      return tr( "cy [px]" );
    case Column::PixelSize:
      return tr( "Pixel [mm]" );
    case Column::Model:
      return tr( "Distortion" );
    case Column::K1:
      return QStringLiteral( "k1" );
    case Column::K2:
      return QStringLiteral( "k2" );
    case Column::P1:
      return QStringLiteral( "p1" );
    case Column::P2:
      return QStringLiteral( "p2" );
    case Column::K3:
      return QStringLiteral( "k3" );
    case Column::Images:
      return tr( "Images" );
    default:
      return QVariant();
  }
}
