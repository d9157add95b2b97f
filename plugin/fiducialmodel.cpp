/***************************************************************************
  fiducialmodel.cpp - the fiducials of a scanned photo as a table
 ***************************************************************************/
#include "fiducialmodel.h"

#include <stdexcept>

GeoStationFiducialModel::GeoStationFiducialModel( QObject *parent )
  : QAbstractTableModel( parent )
{
  reorient();
}

void GeoStationFiducialModel::setCamera( const geostation::Camera &camera )
{
  beginResetModel();
  mFiducials = camera.fiducials;
  mMeasured.clear();
  endResetModel();
  reorient();
}

int GeoStationFiducialModel::rowOf( const QString &fiducialId ) const
{
  for ( size_t i = 0; i < mFiducials.size(); ++i )
    if ( mFiducials[i].id == fiducialId.toStdString() )
      return static_cast<int>( i );
  return -1;
}

void GeoStationFiducialModel::setMeasurement( int row, const std::optional<QPointF> &pixelInScan )
{
  if ( row < 0 || row >= rowCount() )
    return;
  const std::string &id = mFiducials[static_cast<size_t>( row )].id;
  if ( pixelInScan )
    mMeasured[id] = *pixelInScan;
  else
    mMeasured.erase( id );
  reorient();
}

std::optional<QPointF> GeoStationFiducialModel::measurement( int row ) const
{
  if ( row < 0 || row >= rowCount() )
    return std::nullopt;
  const auto m = mMeasured.find( mFiducials[static_cast<size_t>( row )].id );
  return m == mMeasured.end() ? std::nullopt : std::optional<QPointF>( m->second );
}

void GeoStationFiducialModel::reorient()
{
  std::vector<geostation::FiducialMeasurement> measured;
  for ( const auto &[id, pixel] : mMeasured )
    measured.push_back( { id, Eigen::Vector2d( pixel.x(), pixel.y() ) } );
  try
  {
    mSummary = geostation::innerOrientation( mFiducials, measured );
  }
  catch ( const std::exception &e )
  {
    mSummary = geostation::InnerOrientationSummary();
    mSummary.status = geostation::InnerOrientationSummary::Status::TooFewFiducials;
    mSummary.message = e.what();
  }
  if ( rowCount() > 0 )
    emit dataChanged( index( 0, 0 ), index( rowCount() - 1, kColumnCount - 1 ) );
  emit innerOrientationChanged();
}

int GeoStationFiducialModel::rowCount( const QModelIndex &parent ) const
{
  return parent.isValid() ? 0 : static_cast<int>( mFiducials.size() );
}

int GeoStationFiducialModel::columnCount( const QModelIndex &parent ) const
{
  return parent.isValid() ? 0 : kColumnCount;
}

QVariant GeoStationFiducialModel::data( const QModelIndex &index, int role ) const
{
  if ( !index.isValid() || index.row() >= rowCount() )
    return QVariant();
  if ( role == Qt::TextAlignmentRole && index.column() > 0 )
    return QVariant( Qt::AlignRight | Qt::AlignVCenter );
  if ( role != Qt::DisplayRole )
    return QVariant();
  const geostation::Fiducial &f = mFiducials[static_cast<size_t>( index.row() )];
  const std::optional<QPointF> pixel = measurement( index.row() );
  const geostation::FiducialResidual *residual = nullptr;
  if ( mSummary.ok() )
    for ( const geostation::FiducialResidual &r : mSummary.residuals )
      if ( r.id == f.id )
        residual = &r;
  switch ( static_cast<Column>( index.column() ) )
  {
    case Column::Id:
      return QString::fromStdString( f.id );
    case Column::XMm:
      return QString::number( f.photoMm.x(), 'f', 3 );
    case Column::YMm:
      return QString::number( f.photoMm.y(), 'f', 3 );
    case Column::Col:
      return pixel ? QVariant( QString::number( pixel->x(), 'f', 2 ) ) : QVariant();
    case Column::Row:
      return pixel ? QVariant( QString::number( pixel->y(), 'f', 2 ) ) : QVariant();
    case Column::ResidualXUm:
      return residual ? QVariant( QString::number( 1000.0 * residual->residualMm.x(), 'f', 1 ) ) : QVariant();
    case Column::ResidualYUm:
      return residual ? QVariant( QString::number( 1000.0 * residual->residualMm.y(), 'f', 1 ) ) : QVariant();
    default:
      return QVariant();
  }
}

QVariant GeoStationFiducialModel::headerData( int section, Qt::Orientation orientation, int role ) const
{
  if ( orientation != Qt::Horizontal || role != Qt::DisplayRole )
    return QAbstractTableModel::headerData( section, orientation, role );
  switch ( static_cast<Column>( section ) )
  {
    case Column::Id:
      return tr( "Fiducial" );
    case Column::XMm:
      return tr( "x (mm)" );
    case Column::YMm:
      return tr( "y (mm)" );
    case Column::Col:
      return tr( "Col" );
    case Column::Row:
      return tr( "Row" );
    case Column::ResidualXUm:
      return tr( "vx (µm)" );
    case Column::ResidualYUm:
      return tr( "vy (µm)" );
    default:
      return QVariant();
  }
}
