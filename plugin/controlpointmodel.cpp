/***************************************************************************
  controlpointmodel.cpp - the orientation dock's control-point table
 ***************************************************************************/
#include "controlpointmodel.h"

#include <cmath>
#include <stdexcept>

#include <QBrush>
#include <QColor>

GeoStationControlPointModel::GeoStationControlPointModel( QObject *parent )
  : QAbstractTableModel( parent )
{
  reorient();
}

void GeoStationControlPointModel::setCamera( const geostation::Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile )
{
  mCamera = camera;
  mNominalFromFile = nominalFromFile;
  mOffers.clear();
  reorient();
}

void GeoStationControlPointModel::setOptions( const geostation::PhotoOrientationOptions &options )
{
  mOptions = options;
  reorient();
}

int GeoStationControlPointModel::rowOf( const QString &id ) const
{
  for ( size_t i = 0; i < mPoints.size(); ++i )
    if ( mPoints[i].pointId == id.toStdString() )
      return static_cast<int>( i );
  return -1;
}

bool GeoStationControlPointModel::hasGround( int row ) const
{
  return row >= 0 && row < static_cast<int>( mHasGround.size() ) && mHasGround[static_cast<size_t>( row )];
}

int GeoStationControlPointModel::setGroundPoint( const QString &id, const Eigen::Vector3d &worldM )
{
  int row = rowOf( id );
  if ( row < 0 )
  {
    row = rowCount();
    beginInsertRows( QModelIndex(), row, row );
    geostation::PhotoControlPoint point;
    point.pointId = id.toStdString();
    mPoints.push_back( point );
    mHasGround.push_back( false );
    endInsertRows();
  }
  mPoints[static_cast<size_t>( row )].world = worldM;
  mHasGround[static_cast<size_t>( row )] = true;
  reorient();
  return row;
}

int GeoStationControlPointModel::addPoint()
{
  int n = 1;
  while ( rowOf( QStringLiteral( "P%1" ).arg( n ) ) >= 0 )
    ++n;
  const int row = rowCount();
  beginInsertRows( QModelIndex(), row, row );
  geostation::PhotoControlPoint point;
  point.pointId = QStringLiteral( "P%1" ).arg( n ).toStdString();
  mPoints.push_back( point );
  mHasGround.push_back( false );
  endInsertRows();
  reorient();
  return row;
}

bool GeoStationControlPointModel::removePoint( int row )
{
  if ( row < 0 || row >= rowCount() )
    return false;
  beginRemoveRows( QModelIndex(), row, row );
  mOffers.erase( mPoints[static_cast<size_t>( row )].pointId );
  mPoints.erase( mPoints.begin() + row );
  mHasGround.erase( mHasGround.begin() + row );
  endRemoveRows();
  reorient();
  return true;
}

void GeoStationControlPointModel::setPixel( int row, const std::optional<QPointF> &pixelInFile )
{
  if ( row < 0 || row >= rowCount() )
    return;
  geostation::PhotoControlPoint &point = mPoints[static_cast<size_t>( row )];
  point.pixelInFile.reset();
  if ( pixelInFile )
    point.pixelInFile = Eigen::Vector2d( pixelInFile->x(), pixelInFile->y() );
  mOffers.erase( point.pointId );
  reorient();
}

void GeoStationControlPointModel::setRole( int row, geostation::ControlRole role )
{
  if ( row < 0 || row >= rowCount() )
    return;
  mPoints[static_cast<size_t>( row )].role = role;
  reorient();
}

void GeoStationControlPointModel::clear()
{
  beginResetModel();
  mPoints.clear();
  mHasGround.clear();
  mOffers.clear();
  endResetModel();
  reorient();
}

void GeoStationControlPointModel::setOffers( const std::vector<geostation::ControlOffer> &offers )
{
  mOffers.clear();
  for ( const geostation::ControlOffer &offer : offers )
  {
    const int row = rowOf( QString::fromStdString( offer.pointId ) );
    if ( row >= 0 && !mPoints[static_cast<size_t>( row )].pixelInFile )
      mOffers[offer.pointId] = offer;
  }
  if ( rowCount() > 0 )
    emit dataChanged( index( 0, 0 ), index( rowCount() - 1, kColumnCount - 1 ) );
}

int GeoStationControlPointModel::acceptOffers( const QList<int> &rows )
{
  int taken = 0;
  for ( int row = 0; row < rowCount(); ++row )
  {
    geostation::PhotoControlPoint &point = mPoints[static_cast<size_t>( row )];
    const auto offer = mOffers.find( point.pointId );
    if ( offer == mOffers.end() || point.pixelInFile )
      continue;
    const bool found = offer->second.status == geostation::PredictedPoint::Status::Found;
    const bool flagged = offer->second.status == geostation::PredictedPoint::Status::Flagged;
    // every offer found; a flagged one only when the operator picked its row
    if ( !found && !( flagged && rows.contains( row ) ) )
      continue;
    point.pixelInFile = offer->second.pixelInFile;
    mOffers.erase( offer );
    ++taken;
  }
  if ( taken > 0 )
    reorient();
  return taken;
}

void GeoStationControlPointModel::rejectOffers()
{
  mOffers.clear();
  if ( rowCount() > 0 )
    emit dataChanged( index( 0, 0 ), index( rowCount() - 1, kColumnCount - 1 ) );
}

void GeoStationControlPointModel::reorient()
{
  // only points with a ground position take part; the results are mapped back to the rows
  std::vector<geostation::PhotoControlPoint> usable;
  std::vector<int> rowOfUsable;
  for ( size_t i = 0; i < mPoints.size(); ++i )
    if ( mHasGround[i] )
    {
      usable.push_back( mPoints[i] );
      rowOfUsable.push_back( static_cast<int>( i ) );
    }
  geostation::PhotoOrientationSummary summary;
  if ( mCamera.width <= 0 )
    summary.message = tr( "Choose the photo to orient." ).toStdString();
  else
  {
    try
    {
      summary = geostation::orientPhoto( mCamera, mNominalFromFile, usable, mOptions );
    }
    catch ( const std::exception &e )
    {
      summary = geostation::PhotoOrientationSummary();
      summary.status = geostation::PhotoOrientationSummary::Status::Failed;
      summary.message = e.what();
    }
  }
  std::vector<geostation::PhotoControlResult> byRow( mPoints.size() );
  for ( size_t k = 0; k < summary.points.size() && k < rowOfUsable.size(); ++k )
    byRow[static_cast<size_t>( rowOfUsable[k] )] = summary.points[k];
  for ( size_t i = 0; i < mPoints.size(); ++i )
    byRow[i].pointId = mPoints[i].pointId;
  summary.points = byRow;
  mSummary = summary;
  if ( rowCount() > 0 )
    emit dataChanged( index( 0, 0 ), index( rowCount() - 1, kColumnCount - 1 ) );
  emit orientationChanged();
}

int GeoStationControlPointModel::rowCount( const QModelIndex &parent ) const
{
  return parent.isValid() ? 0 : static_cast<int>( mPoints.size() );
}

int GeoStationControlPointModel::columnCount( const QModelIndex &parent ) const
{
  return parent.isValid() ? 0 : kColumnCount;
}

QString GeoStationControlPointModel::statusText( int row ) const
{
  const geostation::PhotoControlPoint &point = mPoints[static_cast<size_t>( row )];
  const geostation::PhotoControlResult &result = mSummary.points[static_cast<size_t>( row )];
  if ( !mHasGround[static_cast<size_t>( row )] )
    return tr( "no ground position" );
  if ( const auto offer = mOffers.find( point.pointId ); offer != mOffers.end() )
    switch ( offer->second.status )
    {
      case geostation::PredictedPoint::Status::Found:
        return tr( "offered: found" );
      case geostation::PredictedPoint::Status::Flagged:
        return tr( "offered, flagged: %1" ).arg( QString::fromStdString( offer->second.reason ) );
      case geostation::PredictedPoint::Status::NotFound:
        return tr( "not found near its prediction" );
      case geostation::PredictedPoint::Status::Outside:
        return tr( "outside the photo" );
    }
  if ( point.role == geostation::ControlRole::Off )
    return tr( "off" );
  if ( !point.pixelInFile )
    return result.projectedInFile && result.inFrame ? tr( "not measured (predicted in the photo)" ) : tr( "not measured" );
  if ( result.blunder )
    return tr( "blunder: w %1, left out" ).arg( result.normalised, 0, 'f', 1 );
  return mSummary.oriented() ? ( point.role == geostation::ControlRole::Check ? tr( "check" ) : tr( "ok" ) ) : tr( "measured" );
}

QVariant GeoStationControlPointModel::data( const QModelIndex &index, int role ) const
{
  if ( !index.isValid() || index.row() >= rowCount() )
    return QVariant();
  const int row = index.row();
  const geostation::PhotoControlPoint &point = mPoints[static_cast<size_t>( row )];
  const geostation::PhotoControlResult &result = mSummary.points[static_cast<size_t>( row )];
  const Column column = static_cast<Column>( index.column() );
  const bool ground = mHasGround[static_cast<size_t>( row )];
  if ( role == Qt::CheckStateRole )
  {
    if ( column == Column::Use )
      return point.role == geostation::ControlRole::Off ? Qt::Unchecked : Qt::Checked;
    if ( column == Column::Check )
      return point.role == geostation::ControlRole::Check ? Qt::Checked : Qt::Unchecked;
    return QVariant();
  }
  if ( role == Qt::ForegroundRole && column == Column::Status && result.blunder )
    return QBrush( QColor( 200, 0, 0 ) );
  if ( role == Qt::ForegroundRole && column == Column::Status && mOffers.count( point.pointId ) )
    return QBrush( mOffers.at( point.pointId ).status == geostation::PredictedPoint::Status::Found ? QColor( 0, 120, 0 ) : QColor( 200, 110, 0 ) );
  if ( role == Qt::TextAlignmentRole && column >= Column::Col && column <= Column::W )
    return QVariant( Qt::AlignRight | Qt::AlignVCenter );
  if ( role != Qt::DisplayRole && role != Qt::EditRole )
    return QVariant();
  auto number = [role]( double value, int decimals ) -> QVariant { return role == Qt::EditRole ? QVariant( value ) : QVariant( QString::number( value, 'f', decimals ) ); };
  // the pixel shown: the measurement, else the offer, else nothing
  std::optional<Eigen::Vector2d> pixel = point.pixelInFile;
  if ( !pixel && mOffers.count( point.pointId ) && ( mOffers.at( point.pointId ).status == geostation::PredictedPoint::Status::Found
                 || mOffers.at( point.pointId ).status == geostation::PredictedPoint::Status::Flagged ) )
    pixel = mOffers.at( point.pointId ).pixelInFile;
  switch ( column )
  {
    case Column::Id:
      return QString::fromStdString( point.pointId );
    case Column::Col:
      return pixel ? number( pixel->x(), 2 ) : QVariant();
    case Column::Row:
      return pixel ? number( pixel->y(), 2 ) : QVariant();
    case Column::X:
      return ground ? number( point.world.x(), 3 ) : QVariant();
    case Column::Y:
      return ground ? number( point.world.y(), 3 ) : QVariant();
    case Column::Z:
      return ground ? number( point.world.z(), 3 ) : QVariant();
    case Column::ResidualCol:
      return result.residualPx ? number( result.residualPx->x(), 2 ) : QVariant();
    case Column::ResidualRow:
      return result.residualPx ? number( result.residualPx->y(), 2 ) : QVariant();
    case Column::ResidualPx:
      return result.residualPx ? number( result.residualPx->norm(), 2 ) : QVariant();
    case Column::GroundErrorM:
      return result.groundErrorM ? number( result.groundErrorM->head<2>().norm(), 3 ) : QVariant();
    case Column::W:
      return result.residualPx && point.role == geostation::ControlRole::Control ? number( result.normalised, 1 ) : QVariant();
    case Column::Status:
      return statusText( row );
    default:
      return QVariant();
  }
}

bool GeoStationControlPointModel::setData( const QModelIndex &index, const QVariant &value, int role )
{
  if ( !index.isValid() || index.row() >= rowCount() )
    return false;
  const int row = index.row();
  geostation::PhotoControlPoint &point = mPoints[static_cast<size_t>( row )];
  const Column column = static_cast<Column>( index.column() );
  if ( role == Qt::CheckStateRole && ( column == Column::Use || column == Column::Check ) )
  {
    const bool on = value.toInt() == Qt::Checked;
    if ( column == Column::Use )
      point.role = on ? geostation::ControlRole::Control : geostation::ControlRole::Off;
    else
      point.role = on ? geostation::ControlRole::Check : geostation::ControlRole::Control;
    reorient();
    return true;
  }
  if ( role != Qt::EditRole )
    return false;
  if ( column == Column::Id )
  {
    const QString id = value.toString().trimmed();
    if ( id.isEmpty() || ( rowOf( id ) >= 0 && rowOf( id ) != row ) )
      return false; // ids stay unique and non-empty
    mOffers.erase( point.pointId );
    point.pointId = id.toStdString();
    reorient();
    return true;
  }
  bool ok = false;
  const double number = value.toDouble( &ok );
  if ( !ok || !std::isfinite( number ) )
    return false;
  switch ( column )
  {
    case Column::Col:
    case Column::Row:
    {
      Eigen::Vector2d pixel = point.pixelInFile.value_or( Eigen::Vector2d( number, number ) );
      ( column == Column::Col ? pixel.x() : pixel.y() ) = number;
      point.pixelInFile = pixel;
      mOffers.erase( point.pointId );
      break;
    }
    case Column::X:
    case Column::Y:
    case Column::Z:
      point.world( static_cast<int>( column ) - static_cast<int>( Column::X ) ) = number;
      mHasGround[static_cast<size_t>( row )] = true;
      break;
    default:
      return false;
  }
  reorient();
  return true;
}

Qt::ItemFlags GeoStationControlPointModel::flags( const QModelIndex &index ) const
{
  if ( !index.isValid() )
    return Qt::NoItemFlags;
  const Column column = static_cast<Column>( index.column() );
  Qt::ItemFlags flags = Qt::ItemIsEnabled | Qt::ItemIsSelectable;
  if ( column == Column::Use || column == Column::Check )
    flags |= Qt::ItemIsUserCheckable;
  if ( column == Column::Id || ( column >= Column::Col && column <= Column::Z ) )
    flags |= Qt::ItemIsEditable;
  return flags;
}

QVariant GeoStationControlPointModel::headerData( int section, Qt::Orientation orientation, int role ) const
{
  if ( orientation != Qt::Horizontal || role != Qt::DisplayRole )
    return QAbstractTableModel::headerData( section, orientation, role );
  switch ( static_cast<Column>( section ) )
  {
    case Column::Id:
      return tr( "ID" );
    case Column::Use:
      return tr( "Use" );
    case Column::Check:
      return tr( "Check" );
    case Column::Col:
      return tr( "Col" );
    case Column::Row:
      return tr( "Row" );
    case Column::X:
      return tr( "X (m)" );
    case Column::Y:
      return tr( "Y (m)" );
    case Column::Z:
      return tr( "Z (m)" );
    case Column::ResidualCol:
      return tr( "dCol (px)" );
    case Column::ResidualRow:
      return tr( "dRow (px)" );
    case Column::ResidualPx:
      return tr( "Residual (px)" );
    case Column::GroundErrorM:
      return tr( "Ground error (m)" );
    case Column::W:
      return tr( "w" );
    case Column::Status:
      return tr( "Status" );
    default:
      return QVariant();
  }
}
