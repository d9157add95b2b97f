/***************************************************************************
  blockinfodialog.cpp - what an opened block contains
 ***************************************************************************/
#include "blockinfodialog.h"

#include <QHeaderView>

#include "cameratablemodel.h"
#include "geometry/crs.h"
#include "io/block.h"

GeoStationBlockInfoDialog::GeoStationBlockInfoDialog( const geostation::Block &block, QWidget *parent )
  : QDialog( parent )
{
  setupUi( this );
  setObjectName( QStringLiteral( "GeoStationBlockInfoDialog" ) );
  mFileLabel->setText( QString::fromStdString( block.sourceFile.string() ) );
  QString crs = QString::fromStdString( block.crs );
  try
  {
    crs += QStringLiteral( " — " ) + QString::fromStdString( geostation::describeCrs( block.crs ).name );
  }
  catch ( const std::exception & )
  {
    // already validated on load; the identifier alone is still right
  }
  mCrsLabel->setText( crs );
  mContentsLabel->setText( contentsSummary( block ) );

  mCameraModel = new GeoStationCameraTableModel( this );
  mCameraModel->setBlock( &block );
  mCameraTable->setModel( mCameraModel );
  mCameraTable->horizontalHeader()->setSectionResizeMode( QHeaderView::ResizeToContents );
  mCameraTable->verticalHeader()->hide();
}

QString GeoStationBlockInfoDialog::contentsSummary( const geostation::Block &block )
{
  int oriented = 0;
  for ( const geostation::BlockImage &image : block.images )
    oriented += image.exterior ? 1 : 0;
  return tr( "%1 cameras, %2 stations, %3 images (%4 oriented)" )
         .arg( block.cameras.size() ).arg( block.stations.size() ).arg( block.images.size() ).arg( oriented );
}
