/***************************************************************************
  fiducialpanel.cpp - the inner orientation of a scanned photo, interactive
 ***************************************************************************/
#include "fiducialpanel.h"

#include <algorithm>

#include <QItemSelectionModel>

#include "backgroundtask.h"
#include "fiducialmodel.h"
#include "imageproc/fiducialdetection.h"

GeoStationFiducialPanel::GeoStationFiducialPanel( QWidget *parent )
  : QWidget( parent )
{
  setupUi( this );
  mModel = new GeoStationFiducialModel( this );
  mFiducialTable->setModel( mModel );
  connect( mModel, &GeoStationFiducialModel::innerOrientationChanged, this, &GeoStationFiducialPanel::updateResult );
  // one button: Detect Fiducials, and while the detection runs (in the background) Cancel Detection
  mDetection = new GeoStationBackgroundTask( this );
  mDetection->attachButton( mDetectButton, [this] { detect(); }, tr( "Cancel Detection" ), tr( "Stops the detection; nothing is measured" ) );
  connect( mDetection, &GeoStationBackgroundTask::progressChanged, this, [this]( double fraction, const QString &text )
  {
    emit message( tr( "Detecting fiducials: %1 %%2" ).arg( static_cast<int>( 100.0 * fraction ) ).arg( text.isEmpty() ? QString() : QStringLiteral( " (" ) + text + ')' ), false );
  } );
  connect( mDetection, &GeoStationBackgroundTask::finished, this, &GeoStationFiducialPanel::takeDetection );
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

bool GeoStationFiducialPanel::detect()
{
  if ( mDetection->isRunning() )
    return false;
  geostation::FiducialDetectionOptions options;
  options.scanPixelMm = mCamera.pixelSizeMm.value_or( 0.0 );
  options.markDiameterPx = mDiameterSpin->value();
  options.brightMark = !mDarkCheck->isChecked();
  if ( !( options.scanPixelMm > 0.0 ) )
  {
    emit message( tr( "Detecting fiducials needs the camera's pixel size (mm)." ), true );
    return false;
  }
  auto detected = std::make_shared<std::array<geostation::DetectedFiducial, 4>>();
  mDetected = detected;
  mDetectingPath = mImagePath;
  mDetection->start( [detected, path = mImagePath.toStdString(), options]( const geostation::Progress &progress )
  {
    geostation::FiducialDetectionOptions run = options;
    run.progress = progress;
    *detected = geostation::detectCornerFiducials( path, run );
  } );
  emit message( tr( "Detecting fiducials in the scan's corners…" ), false );
  return true;
}

void GeoStationFiducialPanel::takeDetection( const QString &error )
{
  int count = 0;
  if ( mDetectingPath != mImagePath )
    emit message( tr( "The fiducials detected in %1 were dropped: another photo was chosen meanwhile." ).arg( mDetectingPath ), true );
  else if ( !error.isEmpty() )
    emit message( tr( "No fiducials detected: %1" ).arg( error ), true );
  else if ( std::all_of( mDetected->begin(), mDetected->end(), []( const geostation::DetectedFiducial &d ) { return d.status == geostation::DetectedFiducial::Status::Cancelled; } ) )
    emit message( tr( "Fiducial detection cancelled; nothing measured." ), true );
  else
  {
    const std::array<geostation::DetectedFiducial, 4> &found = *mDetected;
    const std::array<std::string, 4> ids = geostation::cornerFiducialIds( mCamera.fiducials );
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
  }
  emit detectionFinished( count );
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
