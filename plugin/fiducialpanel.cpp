/***************************************************************************
  fiducialpanel.cpp - the inner orientation of a scanned photo, interactive
 ***************************************************************************/
#include "fiducialpanel.h"

#include <qgsguiutils.h>

#include <QItemSelectionModel>

#include "fiducialmodel.h"
#include "imageproc/fiducialdetection.h"

GeoStationFiducialPanel::GeoStationFiducialPanel( QWidget *parent )
  : QWidget( parent )
{
  setupUi( this );
  mModel = new GeoStationFiducialModel( this );
  mFiducialTable->setModel( mModel );
  connect( mModel, &GeoStationFiducialModel::innerOrientationChanged, this, &GeoStationFiducialPanel::updateResult );
  connect( mDetectButton, &QToolButton::clicked, this, &GeoStationFiducialPanel::detect );
  connect( mMeasureButton, &QToolButton::toggled, this, &GeoStationFiducialPanel::measuringToggled );
}

void GeoStationFiducialPanel::setPhoto( const geostation::Camera &camera, const QString &imagePath, const std::optional<geostation::ImageInnerOrientation> &existing )
{
  mCamera = camera;
  mImagePath = imagePath;
  mExisting = existing;
  mModel->setCamera( camera );
}

bool GeoStationFiducialPanel::measuring() const
{
  return mMeasureButton->isChecked();
}

std::optional<geostation::ImageInnerOrientation> GeoStationFiducialPanel::innerOrientation() const
{
  if ( mModel->oriented() )
    return geostation::ImageInnerOrientation { mModel->summary().photoFromPixel, mModel->summary().sigma0Mm };
  return mExisting;
}

QString GeoStationFiducialPanel::resultText() const
{
  return mResultLabel->text();
}

void GeoStationFiducialPanel::selectRow( int row )
{
  mFiducialTable->selectRow( row );
}

int GeoStationFiducialPanel::detect()
{
  geostation::FiducialDetectionOptions options;
  options.scanPixelMm = mCamera.pixelSizeMm.value_or( 0.0 );
  options.markDiameterPx = mDiameterSpin->value();
  options.brightMark = !mDarkCheck->isChecked();
  if ( !( options.scanPixelMm > 0.0 ) )
  {
    emit message( tr( "Detecting fiducials needs the camera's pixel size (mm)." ), true );
    return 0;
  }
  std::array<geostation::DetectedFiducial, 4> found;
  try
  {
    const QgsTemporaryCursorOverride busy( Qt::WaitCursor ); // the whole scan is read
    found = geostation::detectCornerFiducials( mImagePath.toStdString(), options );
  }
  catch ( const std::exception &e )
  {
    emit message( tr( "No fiducials detected: %1" ).arg( QString::fromStdString( e.what() ) ), true );
    return 0;
  }
  const std::array<std::string, 4> ids = geostation::cornerFiducialIds( mCamera.fiducials );
  int count = 0;
  QStringList missed;
  for ( int k = 0; k < 4; ++k )
  {
    const int row = mModel->rowOf( QString::fromStdString( ids[static_cast<size_t>( k )] ) );
    if ( found[static_cast<size_t>( k )].found() && row >= 0 )
    {
      mModel->setMeasurement( row, QPointF( found[static_cast<size_t>( k )].pixelInImage.x(), found[static_cast<size_t>( k )].pixelInImage.y() ) );
      ++count;
    }
    else if ( row >= 0 )
      missed << QStringLiteral( "%1 (%2)" ).arg( QString::fromStdString( ids[static_cast<size_t>( k )] ), QString::fromStdString( found[static_cast<size_t>( k )].message ) );
  }
  emit message( missed.isEmpty() ? tr( "%1 corner fiducials detected." ).arg( count )
                : tr( "%1 corner fiducials detected; not found: %2. Measure them with a click." ).arg( count ).arg( missed.join( QStringLiteral( ", " ) ) ), !missed.isEmpty() );
  return count;
}

void GeoStationFiducialPanel::measurePixel( const QPointF &pixelInScan )
{
  const QModelIndexList selected = mFiducialTable->selectionModel()->selectedRows();
  int row = selected.isEmpty() ? -1 : selected.first().row();
  for ( int r = 0; row < 0 && r < mModel->rowCount(); ++r )
    if ( !mModel->measurement( r ) )
      row = r;
  if ( row < 0 )
  {
    emit message( tr( "Select the fiducial to measure." ), true );
    return;
  }
  mModel->setMeasurement( row, pixelInScan );
  if ( row + 1 < mModel->rowCount() )
    selectRow( row + 1 );
}

void GeoStationFiducialPanel::updateResult()
{
  const geostation::InnerOrientationSummary &s = mModel->summary();
  if ( !s.ok() )
  {
    mResultLabel->setText( mExisting ? tr( "Inner orientation from the block (σ0 %1 µm). Measured here: %2" ).arg( 1000.0 * mExisting->sigma0Mm, 0, 'f', 1 ).arg( QString::fromStdString( s.message ) )
                           : QString::fromStdString( s.message ) );
  }
  else
  {
    const geostation::AffineDecomposition &d = s.decomposition;
    mResultLabel->setText( tr( "A %1 µm/px, B %2 µm/px, α_A %3°, α_B %4°, affinity %5 %, β %6°; σ0 %7 µm (redundancy %8), RMS residual %9 µm" )
                           .arg( 1000.0 * d.scaleA, 0, 'f', 3 ).arg( 1000.0 * d.scaleB, 0, 'f', 3 ).arg( d.alphaADeg, 0, 'f', 2 ).arg( d.alphaBDeg, 0, 'f', 2 )
                           .arg( d.affinityPct, 0, 'f', 3 ).arg( d.betaDeg, 0, 'f', 3 ).arg( 1000.0 * s.sigma0Mm, 0, 'f', 1 ).arg( s.redundancy ).arg( 1000.0 * s.rmsResidualMm, 0, 'f', 1 ) );
  }
  emit innerOrientationChanged();
}
