/***************************************************************************
  revisiondock.cpp - the Review Map Revision panel
 ***************************************************************************/
#include "revisiondock.h"

#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QPushButton>
#include <QTableView>
#include <QVBoxLayout>

#include <qgsmapcanvas.h>
#include <qgsmaplayercombobox.h>
#include <qgsvectorlayer.h>

#include "revisionreview.h"

GeoStationRevisionDock::GeoStationRevisionDock( QgsMapCanvas *canvas, QWidget *parent )
  : QgsDockWidget( tr( "Review Map Revision" ), parent ), mCanvas( canvas )
{
  setObjectName( QStringLiteral( "GeoStationRevisionDock" ) );
  QWidget *content = new QWidget( this );
  QVBoxLayout *layout = new QVBoxLayout( content );
  QFormLayout *layers = new QFormLayout();
  mRevisionLayer = new QgsMapLayerComboBox( content );
  mRevisionLayer->setFilters( QgsMapLayerProxyModel::LineLayer );
  mRevisionLayer->setToolTip( tr( "geostation:revise_roads' OUTPUT" ) );
  mNewLayer = new QgsMapLayerComboBox( content );
  mNewLayer->setFilters( QgsMapLayerProxyModel::LineLayer );
  mNewLayer->setAllowEmptyLayer( true );
  mNewLayer->setToolTip( tr( "geostation:revise_roads' NEW roads (optional)" ) );
  mMapLayer = new QgsMapLayerComboBox( content );
  mMapLayer->setFilters( QgsMapLayerProxyModel::LineLayer );
  mMapLayer->setToolTip( tr( "The road map that was revised: accepted changes go into its edit buffer" ) );
  layers->addRow( tr( "Revision" ), mRevisionLayer );
  layers->addRow( tr( "New roads" ), mNewLayer );
  layers->addRow( tr( "Map" ), mMapLayer );
  mNotFound = new QComboBox( content );
  mNotFound->addItem( tr( "Flag it (field revision)" ) );
  mNotFound->addItem( tr( "Delete it" ) );
  mNotFound->setToolTip( tr( "What accepting a road that was not found does to its map feature" ) );
  layers->addRow( tr( "Road not found" ), mNotFound );
  layout->addLayout( layers );
  mTable = new QTableView( content );
  mTable->setSelectionBehavior( QAbstractItemView::SelectRows );
  mTable->setSelectionMode( QAbstractItemView::SingleSelection );
  mTable->horizontalHeader()->setStretchLastSection( true );
  layout->addWidget( mTable );
  QHBoxLayout *buttons = new QHBoxLayout();
  mAccept = new QPushButton( tr( "Accept" ), content );
  mAccept->setToolTip( tr( "Write the change into the map's edit buffer (undo takes it back; save the layer to keep it)" ) );
  mReject = new QPushButton( tr( "Reject" ), content );
  mReject->setToolTip( tr( "Keep the map as it is" ) );
  buttons->addWidget( mAccept );
  buttons->addWidget( mReject );
  layout->addLayout( buttons );
  setWidget( content );

  for ( QgsMapLayerComboBox *combo : { mRevisionLayer, mNewLayer, mMapLayer } )
    connect( combo, &QgsMapLayerComboBox::layerChanged, this, &GeoStationRevisionDock::reload );
  connect( mAccept, &QPushButton::clicked, this, [this]
  {
    if ( mReview && currentRow() >= 0 )
      mReview->accept( currentRow(), mNotFound->currentIndex() == 1 ? GeoStationRevisionReview::NotFoundAction::Delete : GeoStationRevisionReview::NotFoundAction::Flag );
  } );
  connect( mReject, &QPushButton::clicked, this, [this]
  {
    if ( mReview && currentRow() >= 0 )
      mReview->reject( currentRow() );
  } );
  reload();
}

GeoStationRevisionDock::~GeoStationRevisionDock() = default;

int GeoStationRevisionDock::currentRow() const
{
  const QModelIndexList rows = mTable->selectionModel() ? mTable->selectionModel()->selectedRows() : QModelIndexList();
  return rows.isEmpty() ? -1 : rows.first().row();
}

void GeoStationRevisionDock::reload()
{
  QgsVectorLayer *revision = qobject_cast<QgsVectorLayer *>( mRevisionLayer->currentLayer() );
  QgsVectorLayer *map = qobject_cast<QgsVectorLayer *>( mMapLayer->currentLayer() );
  mTable->setModel( nullptr );
  mReview.reset();
  const bool usable = GeoStationRevisionReview::isRevisionLayer( revision ) && map && map != revision;
  mAccept->setEnabled( usable );
  mReject->setEnabled( usable );
  if ( !usable )
    return;
  mReview = std::make_unique<GeoStationRevisionReview>( revision, qobject_cast<QgsVectorLayer *>( mNewLayer->currentLayer() ), map );
  connect( mReview.get(), &GeoStationRevisionReview::message, this, &GeoStationRevisionDock::message );
  mTable->setModel( mReview.get() );
  connect( mTable->selectionModel(), &QItemSelectionModel::selectionChanged, this, &GeoStationRevisionDock::showCurrent );
}

void GeoStationRevisionDock::showCurrent()
{
  const int row = currentRow();
  if ( !mReview || row < 0 )
    return;
  const GeoStationRevisionReview::Item &item = mReview->item( row );
  if ( item.layer && mCanvas )
  {
    item.layer->selectByIds( QgsFeatureIds() << item.fid );
    mCanvas->zoomToFeatureIds( item.layer, QgsFeatureIds() << item.fid );
  }
  const GeoStationRevisionReview::Courses courses = mReview->courses( row );
  emit changeSelected( courses.oldCourse, courses.newCourse, courses.crs );
}
