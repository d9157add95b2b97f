/***************************************************************************
  revisionreview.cpp - the changes of a map revision, reviewed into the map
 ***************************************************************************/
#include "revisionreview.h"

#include <algorithm>
#include <stdexcept>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeatureiterator.h>
#include <qgslinestring.h>
#include <qgsproject.h>
#include <qgsvectorlayer.h>

#include "revision/maprevision.h"
#include "io/featureschema.h"

namespace fs = geostation::featureschema;

namespace
{
  std::vector<Eigen::Vector3d> verticesOf( const QgsGeometry &g )
  {
    std::vector<Eigen::Vector3d> out;
    for ( auto v = g.vertices_begin(); v != g.vertices_end(); ++v )
      out.emplace_back( ( *v ).x(), ( *v ).y(), std::isnan( ( *v ).z() ) ? 0.0 : ( *v ).z() );
    return out;
  }

  //! A line of `points` shaped for `layer`: with or without heights, single or multi.
  QgsGeometry lineFor( const QgsVectorLayer *layer, const std::vector<Eigen::Vector3d> &points )
  {
    QVector<double> x, y, z;
    for ( const Eigen::Vector3d &p : points )
    {
      x << p.x();
      y << p.y();
      z << p.z();
    }
    QgsGeometry g( QgsWkbTypes::hasZ( layer->wkbType() ) ? new QgsLineString( x, y, z ) : new QgsLineString( x, y ) );
    if ( QgsWkbTypes::isMultiType( layer->wkbType() ) )
      g.convertToMultiType();
    return g;
  }
} // namespace

GeoStationRevisionReview::GeoStationRevisionReview( QgsVectorLayer *revision, QgsVectorLayer *newRoads, QgsVectorLayer *map, QObject *parent )
  : QAbstractTableModel( parent ), mRevision( revision ), mNewRoads( newRoads ), mMap( map )
{
  load();
}

bool GeoStationRevisionReview::isRevisionLayer( const QgsVectorLayer *layer )
{
  if ( !layer || !layer->isValid() || layer->geometryType() != QgsWkbTypes::LineGeometry )
    return false;
  const QgsFields fields = layer->fields();
  return fields.lookupField( QLatin1String( fs::kRevision ) ) >= 0 && fields.lookupField( QLatin1String( fs::kEvidence ) ) >= 0
         && fields.lookupField( QLatin1String( fs::kShiftM ) ) >= 0 && fields.lookupField( QLatin1String( fs::kSourceFid ) ) >= 0;
}

void GeoStationRevisionReview::load()
{
  QList<Item> changes, added;
  QgsFeature f;
  if ( isRevisionLayer( mRevision ) )
  {
    QgsFeatureIterator it = mRevision->getFeatures();
    while ( it.nextFeature( f ) )
    {
      const QString revision = f.attribute( QLatin1String( fs::kRevision ) ).toString();
      if ( revision != QLatin1String( "moved" ) && revision != QLatin1String( "not_found" ) )
        continue;
      Item item;
      item.change = revision;
      item.layer = mRevision;
      item.fid = f.id();
      item.mapFid = f.attribute( QLatin1String( fs::kSourceFid ) ).toLongLong();
      item.evidence = f.attribute( QLatin1String( fs::kEvidence ) ).toDouble();
      item.shiftM = f.attribute( QLatin1String( fs::kShiftM ) ).toDouble();
      item.lengthM = f.geometry().length();
      changes << item;
    }
  }
  // worst evidence first: the changes an operator should look at hardest
  std::stable_sort( changes.begin(), changes.end(), []( const Item &a, const Item &b ) { return a.evidence < b.evidence; } );
  if ( mNewRoads && mNewRoads->isValid() )
  {
    QgsFeatureIterator it = mNewRoads->getFeatures();
    while ( it.nextFeature( f ) )
    {
      Item item;
      item.change = QStringLiteral( "new" );
      item.layer = mNewRoads;
      item.fid = f.id();
      item.lengthM = f.geometry().length();
      added << item;
    }
  }
  beginResetModel();
  mItems = changes + added;
  endResetModel();
}

int GeoStationRevisionReview::rowCount( const QModelIndex &parent ) const { return parent.isValid() ? 0 : mItems.size(); }
int GeoStationRevisionReview::columnCount( const QModelIndex &parent ) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant GeoStationRevisionReview::data( const QModelIndex &index, int role ) const
{
  if ( !index.isValid() || index.row() >= mItems.size() || ( role != Qt::DisplayRole && role != Qt::ToolTipRole ) )
    return QVariant();
  const Item &item = mItems.at( index.row() );
  switch ( index.column() )
  {
    case Change:
      return item.change == QLatin1String( "not_found" ) ? tr( "not found" ) : item.change == QLatin1String( "new" ) ? tr( "new road" ) : tr( "moved" );
    case Evidence:
      return item.evidence < 0.0 ? QVariant() : QVariant( QString::number( item.evidence, 'f', 2 ) );
    case ShiftM:
      return item.change == QLatin1String( "moved" ) ? QVariant( QString::number( item.shiftM, 'f', 1 ) ) : QVariant();
    case LengthM:
      return QString::number( item.lengthM, 'f', 0 );
    case Decision:
      return item.decision;
    default:
      return QVariant();
  }
}

QVariant GeoStationRevisionReview::headerData( int section, Qt::Orientation orientation, int role ) const
{
  if ( orientation != Qt::Horizontal || role != Qt::DisplayRole )
    return QVariant();
  switch ( section )
  {
    case Change: return tr( "Change" );
    case Evidence: return tr( "Evidence" );
    case ShiftM: return tr( "Shift (m)" );
    case LengthM: return tr( "Length (m)" );
    case Decision: return tr( "Decision" );
    default: return QVariant();
  }
}

QgsGeometry GeoStationRevisionReview::geometryInMapCrs( int row ) const
{
  const Item &item = mItems.at( row );
  QgsFeature f;
  if ( !item.layer || !mMap || !item.layer->getFeatures( QgsFeatureRequest( item.fid ) ).nextFeature( f ) || f.geometry().isNull() )
    return QgsGeometry();
  QgsGeometry g = f.geometry();
  try
  {
    g.transform( QgsCoordinateTransform( item.layer->crs(), mMap->crs(), QgsProject::instance()->transformContext() ) );
  }
  catch ( const QgsCsException & )
  {
    return QgsGeometry();
  }
  return g;
}

GeoStationRevisionReview::Courses GeoStationRevisionReview::courses( int row ) const
{
  const Item &item = mItems.at( row );
  Courses c;
  QgsFeature f;
  if ( !item.layer || !item.layer->getFeatures( QgsFeatureRequest( item.fid ) ).nextFeature( f ) )
    return c;
  c.crs = item.layer->crs();
  if ( item.change == QLatin1String( "not_found" ) )
  {
    c.oldCourse = f.geometry();
    return c;
  }
  c.newCourse = f.geometry();
  QgsFeature mapFeature;
  if ( item.change == QLatin1String( "moved" ) && mMap && mMap->getFeatures( QgsFeatureRequest( item.mapFid ) ).nextFeature( mapFeature ) && !mapFeature.geometry().isNull() )
  {
    c.oldCourse = mapFeature.geometry();
    try
    {
      c.oldCourse.transform( QgsCoordinateTransform( mMap->crs(), c.crs, QgsProject::instance()->transformContext() ) );
    }
    catch ( const QgsCsException & )
    {
      c.oldCourse = QgsGeometry();
    }
  }
  return c;
}

bool GeoStationRevisionReview::acceptMoved( int row )
{
  const Item &item = mItems.at( row );
  QgsFeature mapFeature;
  if ( !mMap->getFeatures( QgsFeatureRequest( item.mapFid ) ).nextFeature( mapFeature ) || mapFeature.geometry().isNull() )
  {
    emit message( tr( "Feature %1 is no longer in %2." ).arg( item.mapFid ).arg( mMap->name() ), true );
    return false;
  }
  if ( mapFeature.geometry().isMultipart() && mapFeature.geometry().constGet()->partCount() > 1 )
  {
    emit message( tr( "Feature %1 of %2 has several parts: edit it by hand." ).arg( item.mapFid ).arg( mMap->name() ), true );
    return false;
  }
  const QgsGeometry course = geometryInMapCrs( row );
  std::vector<Eigen::Vector3d> spliced;
  try
  {
    spliced = geostation::spliceCourse( verticesOf( mapFeature.geometry() ), verticesOf( course ) );
  }
  catch ( const std::invalid_argument &e )
  {
    emit message( QString::fromStdString( e.what() ), true );
    return false;
  }
  mMap->beginEditCommand( tr( "Accept the moved road (feature %1)" ).arg( item.mapFid ) );
  QgsGeometry revised = lineFor( mMap, spliced );
  const bool changed = mMap->changeGeometry( item.mapFid, revised );
  if ( changed )
    mMap->endEditCommand();
  else
    mMap->destroyEditCommand();
  return changed;
}

bool GeoStationRevisionReview::acceptNotFound( const Item &item, NotFoundAction action )
{
  mMap->beginEditCommand( action == NotFoundAction::Delete ? tr( "Delete the road not found (feature %1)" ).arg( item.mapFid )
                                                           : tr( "Flag the road not found (feature %1)" ).arg( item.mapFid ) );
  bool done = false;
  if ( action == NotFoundAction::Delete )
    done = mMap->deleteFeature( item.mapFid );
  else
  {
    int field = mMap->fields().lookupField( QLatin1String( fs::kRevision ) );
    if ( field < 0 && mMap->addAttribute( QgsField( QLatin1String( fs::kRevision ), QVariant::String ) ) )
      field = mMap->fields().lookupField( QLatin1String( fs::kRevision ) );
    done = field >= 0 && mMap->changeAttributeValue( item.mapFid, field, QStringLiteral( "not_found" ) );
  }
  if ( done )
    mMap->endEditCommand();
  else
    mMap->destroyEditCommand();
  return done;
}

bool GeoStationRevisionReview::acceptNew( int row )
{
  const QgsGeometry course = geometryInMapCrs( row );
  if ( course.isNull() )
    return false;
  QgsFeature added( mMap->fields() );
  added.setGeometry( lineFor( mMap, verticesOf( course ) ) );
  mMap->beginEditCommand( tr( "Add the new road" ) );
  const bool done = mMap->addFeature( added );
  if ( done )
    mMap->endEditCommand();
  else
    mMap->destroyEditCommand();
  return done;
}

bool GeoStationRevisionReview::accept( int row, NotFoundAction notFound )
{
  if ( row < 0 || row >= mItems.size() || !mMap || !mMap->isValid() )
    return false;
  const Item &item = mItems.at( row );
  if ( item.decision == QLatin1String( "accepted" ) )
  {
    emit message( tr( "This change was accepted already." ), false );
    return false;
  }
  if ( !mMap->isEditable() && !mMap->startEditing() )
  {
    emit message( tr( "%1 cannot be edited." ).arg( mMap->name() ), true );
    return false;
  }
  const bool done = item.change == QLatin1String( "moved" ) ? acceptMoved( row )
                    : item.change == QLatin1String( "not_found" ) ? acceptNotFound( item, notFound )
                                                                  : acceptNew( row );
  if ( !done )
  {
    emit message( tr( "The change could not be written into %1." ).arg( mMap->name() ), true );
    return false;
  }
  decide( row, QStringLiteral( "accepted" ) );
  mMap->triggerRepaint();
  emit message( tr( "Accepted into %1's edit buffer: save the layer to keep it, undo to take it back." ).arg( mMap->name() ), false );
  return true;
}

void GeoStationRevisionReview::reject( int row )
{
  if ( row >= 0 && row < mItems.size() && mItems.at( row ).decision.isEmpty() )
    decide( row, QStringLiteral( "rejected" ) );
}

void GeoStationRevisionReview::decide( int row, const QString &decision )
{
  mItems[row].decision = decision;
  emit dataChanged( index( row, Decision ), index( row, Decision ) );
}
