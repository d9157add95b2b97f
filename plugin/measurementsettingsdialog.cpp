/***************************************************************************
  measurementsettingsdialog.cpp
 ***************************************************************************/
#include "measurementsettingsdialog.h"

#include <qgsmaplayerproxymodel.h>
#include <qgsproject.h>
#include <qgsrasterlayer.h>

#include "measurementstore.h"
#include "multiviewsession.h"

GeoStationMeasurementSettingsDialog::GeoStationMeasurementSettingsDialog( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QWidget *parent )
  : QDialog( parent )
  , mSession( session )
  , mStore( store )
{
  setupUi( this );
  setObjectName( QStringLiteral( "GeoStationMeasurementSettingsDialog" ) );
  mTargetWidget->setStorageMode( QgsFileWidget::SaveFile );
  mTargetWidget->setFilter( tr( "GeoPackage (*.gpkg)" ) );
  mTargetWidget->setConfirmOverwrite( false );
  mTargetWidget->setFilePath( session->targetGeoPackage().isEmpty() ? session->defaultTargetGeoPackage() : session->targetGeoPackage() );
  mDemCombo->setFilters( QgsMapLayerProxyModel::RasterLayer );
  mDemCombo->setAllowEmptyLayer( true );
  mDemCombo->setLayer( QgsProject::instance()->mapLayer( session->demLayerId() ) );
  mHeightSpin->setValue( session->cameraHeightAboveRoadM() );
  mSigmaSpin->setValue( session->roadPlaneSigmaM() );
  connect( mButtonBox, &QDialogButtonBox::accepted, this, &GeoStationMeasurementSettingsDialog::accept );
  connect( mButtonBox, &QDialogButtonBox::rejected, this, &QDialog::reject );
}

void GeoStationMeasurementSettingsDialog::accept()
{
  QString error;
  if ( !mStore->setTarget( mTargetWidget->filePath(), &error ) )
  {
    mErrorLabel->setText( error );
    return;
  }
  mSession->setDemLayerId( mDemCombo->currentLayer() ? mDemCombo->currentLayer()->id() : QString() );
  mSession->setRoadPlane( mHeightSpin->value(), mSigmaSpin->value() );
  QDialog::accept();
}
