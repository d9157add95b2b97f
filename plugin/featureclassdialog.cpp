/***************************************************************************
  featureclassdialog.cpp
 ***************************************************************************/
#include "featureclassdialog.h"

#include <QHeaderView>

GeoStationFeatureClassDialog::GeoStationFeatureClassDialog( const QList<GeoStationFeatureClass> &classes, QWidget *parent )
  : QDialog( parent )
{
  setupUi( this );
  setObjectName( QStringLiteral( "GeoStationFeatureClassDialog" ) );
  mModel = new GeoStationFeatureClassModel( this );
  mModel->setClasses( classes );
  mClassTable->setModel( mModel );
  mClassTable->horizontalHeader()->setStretchLastSection( true );
  const auto add = [this]( GeoStationFeatureClass::Geometry geometry )
  {
    const int row = mModel->addClass( geometry );
    mClassTable->setCurrentIndex( mModel->index( row, static_cast<int>( GeoStationFeatureClassModel::Column::Name ) ) );
    mClassTable->edit( mModel->index( row, static_cast<int>( GeoStationFeatureClassModel::Column::Name ) ) );
  };
  connect( mAddPointButton, &QPushButton::clicked, this, [add] { add( GeoStationFeatureClass::Geometry::Point ); } );
  connect( mAddLineButton, &QPushButton::clicked, this, [add] { add( GeoStationFeatureClass::Geometry::Line ); } );
  connect( mAddPolygonButton, &QPushButton::clicked, this, [add] { add( GeoStationFeatureClass::Geometry::Polygon ); } );
  connect( mRemoveButton, &QPushButton::clicked, this, [this] { mModel->removeClassAt( mClassTable->currentIndex().row() ); } );
  connect( mButtonBox, &QDialogButtonBox::accepted, this, &GeoStationFeatureClassDialog::accept );
  connect( mButtonBox, &QDialogButtonBox::rejected, this, &QDialog::reject );
}

void GeoStationFeatureClassDialog::accept()
{
  QString error;
  if ( !mModel->validate( &error ) )
  {
    mErrorLabel->setText( error );
    return;
  }
  QDialog::accept();
}
