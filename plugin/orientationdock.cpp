/***************************************************************************
  orientationdock.cpp - orienting one photo interactively
 ***************************************************************************/
#include "orientationdock.h"

#include <qgsguiutils.h>

#include <cmath>
#include <filesystem>

#include <QFileInfo>
#include <QItemSelectionModel>
#include <QRegularExpression>

#include <qgscoordinatetransform.h>
#include <qgsfeatureiterator.h>
#include <qgsmapcanvas.h>
#include <qgsproject.h>
#include <qgsrasterdataprovider.h>
#include <qgsrasterlayer.h>
#include <qgsvectorlayer.h>

#include "controlpointmodel.h"
#include "controlpointoverlay.h"
#include "fiducialpanel.h"
#include "groundpoints.h"
#include "layerinphoto.h"
#include "mappointtool.h"
#include "identification/markcandidates.h"
#include "identification/photoidentification.h"
#include "backgroundtask.h"
#include "io/rasterfile.h"
#include "multiviewdock.h"
#include "multiviewsession.h"

GeoStationOrientationDock::GeoStationOrientationDock( GeoStationMultiviewSession *session, GeoStationMultiviewDock *multiview, QgsMapCanvas *mapCanvas, QWidget *parent )
  : QgsDockWidget( tr( "GeoStation Photo Orientation" ), parent )
  , mSession( session )
  , mMultiview( multiview )
  , mMapCanvas( mapCanvas )
{
  setObjectName( QStringLiteral( "GeoStationOrientationDock" ) );
  QWidget *content = new QWidget( this );
  setupUi( content );
  setWidget( content );
  mModel = new GeoStationControlPointModel( this );
  mOverlay = std::make_unique<GeoStationControlPointOverlay>();
  mTable->setModel( mModel );
  mControlLayerCombo->setFilters( QgsMapLayerProxyModel::PointLayer );
  mOverlayLayerCombo->setFilters( QgsMapLayerProxyModel::VectorLayer );
  mLayerInPhoto = new GeoStationLayerInPhoto( mSession, mMultiview, this );
  auto overlayLayer = [this] { mLayerInPhoto->setLayer( mShowOverlayCheck->isChecked() ? qobject_cast<QgsVectorLayer *>( mOverlayLayerCombo->currentLayer() ) : nullptr ); };
  connect( mOverlayLayerCombo, &QgsMapLayerComboBox::layerChanged, this, overlayLayer );
  connect( mShowOverlayCheck, &QCheckBox::toggled, this, overlayLayer );

  connect( mModel, &GeoStationControlPointModel::orientationChanged, this, &GeoStationOrientationDock::updateOrientation );
  connect( mImageCombo, qOverload<int>( &QComboBox::activated ), this, [this]( int ) { setImage( mImageCombo->currentData().toString() ); } );
  connect( mLoadControlButton, &QPushButton::clicked, this, [this] { loadControlLayer( qobject_cast<QgsVectorLayer *>( mControlLayerCombo->currentLayer() ) ); } );
  connect( mMeasurePhotoButton, &QToolButton::toggled, this, &GeoStationOrientationDock::setMeasuring );
  connect( mFiducialPanel, &GeoStationFiducialPanel::measuringToggled, this, &GeoStationOrientationDock::setMeasuring );
  connect( mFiducialPanel, &GeoStationFiducialPanel::message, this, &GeoStationOrientationDock::showMessage );
  connect( mFiducialPanel, &GeoStationFiducialPanel::innerOrientationChanged, this, &GeoStationOrientationDock::applyInnerOrientation );
  connect( mPickMapButton, &QToolButton::toggled, this, &GeoStationOrientationDock::setPickingGround );
  connect( mAddButton, &QToolButton::clicked, this, [this] { selectRow( mModel->addPoint() ); } );
  connect( mRemoveButton, &QToolButton::clicked, this, [this]
  {
    QList<int> rows = selectedRows();
    std::sort( rows.begin(), rows.end(), std::greater<int>() );
    for ( int row : rows )
      mModel->removePoint( row );
  } );
  connect( mRefineButton, &QToolButton::clicked, this, &GeoStationOrientationDock::refineSelected );
  connect( mPredictButton, &QToolButton::clicked, this, &GeoStationOrientationDock::predictAndFind );
  // one button: Identify Automatically, and while the search runs (in the background) Cancel Identification
  mIdentification = new GeoStationBackgroundTask( this );
  mIdentification->attachButton( mIdentifyButton, [this] { identifyAutomatically(); }, tr( "Cancel Identification" ), tr( "Stops the search; nothing is offered" ) );
  connect( mIdentification, &GeoStationBackgroundTask::progressChanged, this, [this]( double fraction, const QString &text )
  {
    showMessage( tr( "Identifying control: %1 %%2" ).arg( static_cast<int>( 100.0 * fraction ) ).arg( text.isEmpty() ? QString() : QStringLiteral( " (" ) + text + ')' ) );
  } );
  connect( mIdentification, &GeoStationBackgroundTask::finished, this, &GeoStationOrientationDock::takeIdentification );
  connect( mAcceptButton, &QToolButton::clicked, this, &GeoStationOrientationDock::acceptFound );
  connect( mRejectButton, &QToolButton::clicked, mModel, &GeoStationControlPointModel::rejectOffers );
  connect( mSaveButton, &QPushButton::clicked, this, &GeoStationOrientationDock::saveToBlock );
  for ( QCheckBox *box : { mFreeF, mFreeCx, mFreeCy, mFreeK1, mFreeK2, mFreeP1, mFreeP2, mFreeK3 } )
    connect( box, &QCheckBox::toggled, this, &GeoStationOrientationDock::updateFreeParameters );
  connect( mSession, &GeoStationMultiviewSession::blockChanged, this, &GeoStationOrientationDock::updateImageChoices );
  connect( mSession, &GeoStationMultiviewSession::viewImagesChanged, this, &GeoStationOrientationDock::drawMarkers );
  // the block read again (after Save, or written by an algorithm): the photo list and the camera line say what it holds now
  connect( mSession, &GeoStationMultiviewSession::blockReloaded, this, [this]
  {
    updateImageChoices();
    updateCameraLabel();
  } );
  if ( mMultiview )
    connect( mMultiview, &GeoStationMultiviewDock::imagePixelPicked, this, [this]( const QString &imageId, QPointF pixel )
  {
    if ( imageId == mImageId && mFiducialPanel->measuring() )
      mFiducialPanel->measurePixel( pixel );
    else if ( imageId == mImageId )
      measurePixel( pixel );
    else
      showMessage( tr( "That view shows %1; the photo being oriented is %2." ).arg( imageId, mImageId ), true );
  } );
  updateImageChoices();
}

GeoStationOrientationDock::~GeoStationOrientationDock()
{
  if ( mMultiview )
    mMultiview->setPickingRedirected( false );
  mOverlay->clear();
  if ( mMapCanvas && mGroundTool && mMapCanvas->mapTool() == mGroundTool )
    mMapCanvas->unsetMapTool( mGroundTool );
  delete mGroundTool;
}


void GeoStationOrientationDock::showMessage( const QString &text, bool warning )
{
  mMessage = text;
  mMessageLabel->setText( text );
  mMessageLabel->setStyleSheet( warning ? QStringLiteral( "color: #b00000" ) : QString() );
  emit messageShown( text, warning );
}

void GeoStationOrientationDock::updateImageChoices()
{
  mImageCombo->clear();
  if ( !mSession->block() )
  {
    mImageId.clear();
    mModel->setCamera( geostation::Camera(), std::nullopt );
    return;
  }
  for ( const geostation::BlockImage &image : mSession->block()->images )
    mImageCombo->addItem( QStringLiteral( "%1%2" ).arg( QString::fromStdString( image.id ), image.exterior ? QString() : tr( " (not oriented)" ) ),
                          QString::fromStdString( image.id ) );
  // a reload of the same block (after Save) keeps the photo and its measurements
  const int index = mImageCombo->findData( mImageId );
  if ( index >= 0 )
    mImageCombo->setCurrentIndex( index );
  else if ( mImageCombo->count() > 0 )
    setImage( mImageCombo->itemData( 0 ).toString() );
}

bool GeoStationOrientationDock::setImage( const QString &imageId )
{
  const geostation::Block *block = mSession->block();
  const geostation::BlockImage *image = block ? block->findImage( imageId.toStdString() ) : nullptr;
  if ( !image )
  {
    showMessage( tr( "The block has no photo %1." ).arg( imageId ), true );
    return false;
  }
  const geostation::Camera *camera = block->findCamera( image->cameraId );
  if ( !camera )
  {
    showMessage( tr( "Photo %1 cannot be oriented: its camera %2 is not in the block." ).arg( imageId, QString::fromStdString( image->cameraId ) ), true );
    return false;
  }
  mImageId = imageId;
  mImageCombo->setCurrentIndex( mImageCombo->findData( imageId ) );
  mGrey.release();
  mGreyImageId.clear();
  mModel->clear();
  mModel->setCamera( *camera, std::nullopt );
  // a film camera: its fiducials, and the scan affine of the inner orientation the block has (or that is measured here)
  mTabs->setTabEnabled( mTabs->indexOf( mFiducialTab ), !camera->fiducials.empty() );
  mTabs->setCurrentWidget( !camera->fiducials.empty() && !image->innerOrientation ? mFiducialTab : mControlTab );
  mFiducialPanel->setPhoto( *camera, mSession->imagePath( imageId ), image->innerOrientation );
  updateCameraLabel();
  // the measurements saved with the photo last time
  const QString tablePath = controlTablePath();
  if ( QFileInfo::exists( tablePath ) )
  {
    try
    {
      for ( const geostation::PhotoControlPoint &p : geostation::readPhotoControlTable( tablePath.toStdString() ) )
      {
        const int row = mModel->setGroundPoint( QString::fromStdString( p.pointId ), p.world );
        if ( p.pixelInFile )
          mModel->setPixel( row, QPointF( p.pixelInFile->x(), p.pixelInFile->y() ) );
        mModel->setRole( row, p.role );
      }
      showMessage( tr( "%n point(s) read from %1.", nullptr, mModel->rowCount() ).arg( QFileInfo( tablePath ).fileName() ) );
    }
    catch ( const std::exception &e )
    {
      showMessage( QString::fromStdString( e.what() ), true );
    }
  }
  if ( mMultiview && mMultiview->viewCount() > 0 && !mSession->viewImages().contains( imageId ) )
    mMultiview->setViewImage( 0, imageId );
  drawMarkers();
  return true;
}

void GeoStationOrientationDock::updateCameraLabel()
{
  const geostation::Block *block = mSession->block();
  const geostation::BlockImage *image = block ? block->findImage( mImageId.toStdString() ) : nullptr;
  const geostation::Camera *camera = image ? block->findCamera( image->cameraId ) : nullptr;
  if ( !camera )
  {
    mCameraLabel->clear();
    return;
  }
  const bool film = !camera->fiducials.empty();
  mCameraLabel->setText( tr( "%1: %2 × %3 px, f %4 px%5%6" )
                         .arg( QString::fromStdString( camera->id ) ).arg( camera->width ).arg( camera->height ).arg( camera->f, 0, 'f', 1 )
                         .arg( image->innerOrientation ? tr( ", scanned film (pixels of the scan, through its inner orientation)" )
                               : film ? tr( ", film camera without inner orientation yet: detect or measure its fiducials" ) : QString() )
                         .arg( image->exterior ? tr( "; oriented" ) : tr( "; not oriented yet" ) ) );
}

QString GeoStationOrientationDock::controlTablePath() const
{
  const QFileInfo block( mSession->blockPath() );
  QString stem = block.fileName();
  stem.remove( QStringLiteral( ".geostation.json" ) );
  stem.remove( QStringLiteral( ".json" ) );
  QString image = mImageId;
  image.replace( QRegularExpression( QStringLiteral( "[^A-Za-z0-9_.-]" ) ), QStringLiteral( "_" ) );
  return block.absoluteDir().filePath( QStringLiteral( "%1.%2.control.csv" ).arg( stem, image ) );
}

int GeoStationOrientationDock::loadControlLayer( QgsVectorLayer *layer )
{
  if ( !layer || !mSession->block() )
  {
    showMessage( tr( "Choose a point layer of control points (and open a block) first." ), true );
    return 0;
  }
  const GeoStationGroundPoints::ControlLayerPoints read = GeoStationGroundPoints::readControlLayer( layer, mSession );
  for ( const auto &[id, world] : read.points )
    mModel->setGroundPoint( id, world );
  const int count = read.points.size();
  showMessage( read.withoutHeight ? tr( "%1 control points read from %2; %3 left out without a height (no Z, no height field, not on the DEM layer)." ).arg( count ).arg( layer->name() ).arg( read.withoutHeight )
               : tr( "%1 control points read from %2." ).arg( count ).arg( layer->name() ), read.withoutHeight > 0 );
  return count;
}

QList<int> GeoStationOrientationDock::selectedRows() const
{
  QList<int> rows;
  for ( const QModelIndex &index : mTable->selectionModel()->selectedRows() )
    rows << index.row();
  return rows;
}

void GeoStationOrientationDock::selectRow( int row )
{
  mTable->selectRow( row );
}

void GeoStationOrientationDock::measurePixel( const QPointF &pixelInFile )
{
  QList<int> rows = selectedRows();
  int row = rows.isEmpty() ? -1 : rows.first();
  for ( int r = 0; row < 0 && r < mModel->rowCount(); ++r )
    if ( !mModel->points()[static_cast<size_t>( r )].pixelInFile )
      row = r;
  if ( row < 0 )
    row = mModel->addPoint();
  mModel->setPixel( row, pixelInFile );
  showMessage( tr( "%1 measured at col %2, row %3." ).arg( QString::fromStdString( mModel->points()[static_cast<size_t>( row )].pointId ) )
               .arg( pixelInFile.x(), 0, 'f', 2 ).arg( pixelInFile.y(), 0, 'f', 2 ) );
  // on to the next point not measured, so a run of clicks measures the list in order
  for ( int r = 1; r <= mModel->rowCount(); ++r )
  {
    const int next = ( row + r ) % mModel->rowCount();
    if ( !mModel->points()[static_cast<size_t>( next )].pixelInFile && mModel->hasGround( next ) )
    {
      selectRow( next );
      return;
    }
  }
}

bool GeoStationOrientationDock::pickGround( const QgsPointXY &pointInCanvasCrs )
{
  if ( !mSession->block() )
    return false;
  QgsPointXY xy;
  try
  {
    const QgsCoordinateReferenceSystem canvasCrs = mMapCanvas ? mMapCanvas->mapSettings().destinationCrs() : mSession->crs();
    xy = QgsCoordinateTransform( canvasCrs, mSession->crs(), QgsProject::instance() ).transform( pointInCanvasCrs );
  }
  catch ( const QgsCsException & )
  {
    showMessage( tr( "The clicked point cannot be transformed into the block's CRS." ), true );
    return false;
  }
  QString why;
  const std::optional<double> height = GeoStationGroundPoints::demHeight( mSession, xy, &why );
  if ( !height )
  {
    showMessage( tr( "No ground position taken: %1." ).arg( why ), true );
    return false;
  }
  const QList<int> rows = selectedRows();
  const int row = rows.isEmpty() ? mModel->addPoint() : rows.first();
  const QString id = QString::fromStdString( mModel->points()[static_cast<size_t>( row )].pointId );
  mModel->setGroundPoint( id, Eigen::Vector3d( xy.x(), xy.y(), *height ) );
  showMessage( tr( "%1 on the ground at %2, %3, height %4 m from the DEM." ).arg( id ).arg( xy.x(), 0, 'f', 2 ).arg( xy.y(), 0, 'f', 2 ).arg( *height, 0, 'f', 2 ) );
  return true;
}

const cv::Mat &GeoStationOrientationDock::photoGrey()
{
  if ( mGreyImageId != mImageId || mGrey.empty() )
  {
    mGrey.release();
    mGreyImageId = mImageId;
    try
    {
      const geostation::Block *block = mSession->block();
      mGrey = geostation::markGrey( geostation::readRaster( block->imageFilePath( block->image( mImageId.toStdString() ) ).string() ).pixels );
    }
    catch ( const std::exception &e )
    {
      showMessage( tr( "The photo cannot be read: %1" ).arg( QString::fromStdString( e.what() ) ), true );
    }
  }
  return mGrey;
}

int GeoStationOrientationDock::refineSelected()
{
  const cv::Mat &grey = photoGrey();
  if ( grey.empty() )
    return 0;
  int moved = 0, missed = 0;
  for ( int row : selectedRows() )
  {
    const std::optional<Eigen::Vector2d> pixel = mModel->points()[static_cast<size_t>( row )].pixelInFile;
    if ( !pixel )
      continue;
    if ( const std::optional<Eigen::Vector2d> centre = geostation::refineMarkPixel( grey, *pixel ) )
    {
      mModel->setPixel( row, QPointF( centre->x(), centre->y() ) );
      ++moved;
    }
    else
      ++missed;
  }
  showMessage( missed ? tr( "%1 points moved onto their marks; no mark near %2 of them." ).arg( moved ).arg( missed ) : tr( "%n point(s) moved onto their marks.", nullptr, moved ), missed > 0 );
  return moved;
}

int GeoStationOrientationDock::predictAndFind()
{
  const geostation::Block *block = mSession->block();
  const geostation::BlockImage *image = block ? block->findImage( mImageId.toStdString() ) : nullptr;
  // the orientation measured; else the block's (e.g. GNSS/INS); else from three points, or two and the camera's position
  std::vector<geostation::ExteriorOrientation> candidates;
  if ( mModel->summary().oriented() )
    candidates.push_back( mModel->summary().resection.exterior );
  else if ( image && image->exterior )
    candidates.push_back( *image->exterior );
  else
  {
    std::optional<Eigen::Vector3d> centre;
    const QStringList xyz = mApproxCentreEdit->text().simplified().split( QLatin1Char( ' ' ), Qt::SkipEmptyParts );
    bool okX = false, okY = false, okZ = false;
    if ( xyz.size() == 3 )
    {
      const Eigen::Vector3d c( xyz[0].toDouble( &okX ), xyz[1].toDouble( &okY ), xyz[2].toDouble( &okZ ) );
      if ( okX && okY && okZ )
        centre = c;
    }
    if ( !mApproxCentreEdit->text().trimmed().isEmpty() && !centre )
    {
      showMessage( tr( "The approximate camera position must read \"X Y Z\" (block CRS, metres)." ), true );
      return 0;
    }
    candidates = geostation::approximatePhotoOrientations( mModel->camera(), mModel->nominalFromFile(), mModel->points(), centre );
  }
  if ( candidates.empty() )
  {
    showMessage( tr( "Measure three points first, or two and give the camera's approximate position: the others are predicted from the orientation." ), true );
    return 0;
  }
  const cv::Mat &grey = photoGrey();
  if ( grey.empty() )
    return 0;
  std::vector<geostation::ControlOffer> offers;
  int chosen = -1;
  try
  {
    offers = geostation::offerPredictedControl( grey, mModel->camera(), mModel->nominalFromFile(), candidates, mModel->points(), &chosen );
  }
  catch ( const std::exception &e )
  {
    showMessage( tr( "No prediction: %1" ).arg( QString::fromStdString( e.what() ) ), true );
    return 0;
  }
  mModel->setOffers( offers );
  int found = 0, flagged = 0, notFound = 0;
  for ( const geostation::ControlOffer &offer : offers )
  {
    found += offer.status == geostation::PredictedPoint::Status::Found ? 1 : 0;
    flagged += offer.status == geostation::PredictedPoint::Status::Flagged ? 1 : 0;
    notFound += offer.status == geostation::PredictedPoint::Status::NotFound ? 1 : 0;
  }
  showMessage( tr( "%1 points found near their predictions, %2 flagged (check them before accepting), %3 not found%4." ).arg( found ).arg( flagged ).arg( notFound )
               .arg( candidates.size() > 1 ? tr( " (of %1 possible orientations from three points, the one under which the most marks were found)" ).arg( candidates.size() ) : QString() ) );
  drawMarkers();
  return found;
}

bool GeoStationOrientationDock::identifyAutomatically()
{
  if ( mIdentification->isRunning() )
    return false;
  const cv::Mat &grey = photoGrey();
  if ( grey.empty() )
    return false;
  std::vector<geostation::ControlPoint> control;
  for ( const geostation::PhotoControlPoint &p : mModel->points() )
    if ( p.role != geostation::ControlRole::Off )
      control.push_back( { p.pointId, p.world, p.sigmaM, false } );
  geostation::PhotoIdentificationOptions options;
  const std::optional<geostation::OrientedImage> current = currentOrientation();
  if ( current )
    options.identification.approximate = current->exterior(); // narrows the search to the marks near each prediction
  // the search works on its own references: the photo's grey levels are shared (a new photo replaces them,
  // it does not write into them), the camera and control copied
  auto result = std::make_shared<geostation::PhotoIdentificationSummary>();
  mIdentificationResult = result;
  mIdentification->start( [result, grey, camera = mModel->camera(), nominal = mModel->nominalFromFile(), control, options]( const geostation::Progress &progress )
  {
    geostation::PhotoIdentificationOptions run = options;
    run.identification.progress = progress;
    *result = geostation::identifyControlInPhoto( grey, camera, nominal, control, run );
  } );
  mIdentifyingImageId = mImageId;
  showMessage( tr( "Identifying control among the photo's marks…" ) );
  return true;
}

void GeoStationOrientationDock::takeIdentification( const QString &error )
{
  const geostation::PhotoIdentificationSummary &result = *mIdentificationResult;
  int identified = 0;
  if ( mIdentifyingImageId != mImageId )
    showMessage( tr( "The control identified in %1 was dropped: another photo was chosen meanwhile." ).arg( mIdentifyingImageId ), true );
  else if ( !error.isEmpty() )
    showMessage( tr( "No control identified: %1" ).arg( error ), true );
  else if ( result.identification.status == geostation::ControlIdentificationSummary::Status::Cancelled )
    showMessage( tr( "Identification cancelled; nothing offered." ), true );
  else if ( !result.ok() )
    showMessage( tr( "No control identified among %1 marks: %2." ).arg( result.candidates ).arg( QString::fromStdString( result.identification.message ) ), true );
  else
  {
    std::vector<geostation::ControlOffer> offers;
    for ( const geostation::PhotoIdentifiedPoint &p : result.identified )
      offers.push_back( { p.pointId, geostation::PredictedPoint::Status::Found, std::string(), p.pixelInFile, p.predictedInFile } );
    for ( const geostation::PhotoIdentifiedPoint &p : result.flagged )
      offers.push_back( { p.pointId, geostation::PredictedPoint::Status::Flagged,
                          tr( "%1 px from its prediction" ).arg( ( p.pixelInFile - p.predictedInFile ).norm(), 0, 'f', 1 ).toStdString(), p.pixelInFile, p.predictedInFile } );
    mModel->setOffers( offers );
    showMessage( tr( "%1 control points identified among %2 marks (chance explains it with odds %3); accept them with Accept Found." )
                 .arg( result.identified.size() ).arg( result.candidates ).arg( result.identification.falseAlarms, 0, 'g', 2 ) );
    drawMarkers();
    identified = static_cast<int>( result.identified.size() );
  }
  emit identificationFinished( identified );
}

int GeoStationOrientationDock::acceptFound()
{
  const int taken = mModel->acceptOffers( selectedRows() );
  showMessage( tr( "%n offer(s) accepted.", nullptr, taken ) );
  return taken;
}

bool GeoStationOrientationDock::saveToBlock()
{
  const geostation::PhotoOrientationSummary &summary = mModel->summary();
  if ( !mSession->block() || !summary.oriented() )
  {
    showMessage( tr( "Nothing saved: %1" ).arg( QString::fromStdString( summary.message ) ), true );
    return false;
  }
  try
  {
    geostation::Block block = *mSession->block();
    geostation::applyPhotoOrientation( block, mImageId.toStdString(), summary, mModel->options() );
    if ( const std::optional<geostation::ImageInnerOrientation> inner = mFiducialPanel->innerOrientation() )
      for ( geostation::BlockImage &image : block.images )
        if ( image.id == mImageId.toStdString() )
          image.innerOrientation = inner;
    // the measurements first: a block saved without them could not be reproduced
    geostation::writePhotoControlTable( controlTablePath().toStdString(), mImageId.toStdString(), mModel->points() );
    block.save( mSession->blockPath().toStdString() );
  }
  catch ( const std::exception &e )
  {
    showMessage( tr( "Nothing saved: %1" ).arg( QString::fromStdString( e.what() ) ), true );
    return false;
  }
  mSession->reloadBlock();
  const QString saved = tr( "The orientation of %1 is saved in %2; the measurements in %3." )
                          .arg( mImageId, QFileInfo( mSession->blockPath() ).fileName(), QFileInfo( controlTablePath() ).fileName() );
  if ( mDemCoverage && !mDemCoverage->complete() )
    showMessage( tr( "%1 Note: %2." ).arg( saved, QString::fromStdString( mDemCoverage->message ) ), true );
  else
    showMessage( saved );
  return true;
}

void GeoStationOrientationDock::setMeasuring( bool )
{
  const bool on = mMeasurePhotoButton->isChecked() || mFiducialPanel->measuring();
  if ( mMultiview )
    mMultiview->setPickingRedirected( on );
  if ( on && mPickMapButton->isChecked() )
    mPickMapButton->setChecked( false );
}

void GeoStationOrientationDock::applyInnerOrientation()
{
  std::optional<Eigen::Matrix<double, 2, 3>> nominalFromFile;
  if ( const std::optional<geostation::ImageInnerOrientation> inner = mFiducialPanel->innerOrientation() )
  {
    try
    {
      nominalFromFile = geostation::nominalFromScanAffine( mModel->camera(), *inner );
    }
    catch ( const std::exception &e )
    {
      showMessage( tr( "The inner orientation cannot be used: %1" ).arg( QString::fromStdString( e.what() ) ), true );
    }
  }
  // the control points keep their pixels (the scan's): only the way to the camera's frame changes
  mModel->setCamera( mModel->camera(), nominalFromFile );
}

void GeoStationOrientationDock::setPickingGround( bool on )
{
  if ( !mMapCanvas )
    return;
  if ( on )
  {
    if ( !mGroundTool )
    {
      mGroundTool = new GeoStationMapPointTool( mMapCanvas, Qt::CrossCursor );
      connect( mGroundTool, &GeoStationMapPointTool::picked, this, &GeoStationOrientationDock::pickGround );
      connect( mGroundTool, &QgsMapTool::deactivated, this, [this] { mPickMapButton->setChecked( false ); } );
    }
    mMapCanvas->setMapTool( mGroundTool );
  }
  else if ( mGroundTool && mMapCanvas->mapTool() == mGroundTool )
    mMapCanvas->unsetMapTool( mGroundTool );
}

void GeoStationOrientationDock::updateFreeParameters()
{
  geostation::PhotoOrientationOptions options = mModel->options();
  const QCheckBox *boxes[] = { mFreeF, mFreeCx, mFreeCy, mFreeK1, mFreeK2, mFreeP1, mFreeP2, mFreeK3 };
  for ( int i = 0; i < geostation::kInteriorSize; ++i )
    options.freeInterior[static_cast<size_t>( i )] = boxes[i]->isChecked();
  mModel->setOptions( options );
}

std::optional<geostation::OrientedImage> GeoStationOrientationDock::currentOrientation() const
{
  // the orientation being measured when there is one, else the block's
  std::optional<geostation::OrientedImage> oriented;
  const geostation::PhotoOrientationSummary &summary = mModel->summary();
  const geostation::BlockImage *image = mSession->block() ? mSession->block()->findImage( mImageId.toStdString() ) : nullptr;
  if ( summary.oriented() )
    oriented.emplace( summary.resection.camera, summary.resection.exterior );
  else if ( image && image->exterior && mModel->camera().width > 0 )
    oriented.emplace( mModel->camera(), *image->exterior );
  if ( oriented && mModel->nominalFromFile() )
    oriented->setScanAffine( *mModel->nominalFromFile() );
  return oriented;
}

int GeoStationOrientationDock::markerCount() const
{
  return mOverlay->markerCount();
}

QString GeoStationOrientationDock::resultText() const
{
  return mResultText->toPlainText();
}

void GeoStationOrientationDock::updateOrientation()
{
  const geostation::PhotoOrientationSummary &summary = mModel->summary();
  QStringList lines;
  lines << QString::fromStdString( summary.message );
  if ( summary.oriented() )
  {
    const geostation::ResectionSummary &r = summary.resection;
    lines << tr( "σ0 %1 (redundancy %2, %3 iterations)" ).arg( r.sigma0, 0, 'f', 2 ).arg( r.redundancy ).arg( r.iterations );
    for ( size_t i = 0; i < r.parameterNames.size(); ++i )
    {
      const bool angle = i >= 3 && i < 6;
      const int decimals = angle ? 4 : 3;
      const QString unit = i < 3 ? tr( " m" ) : angle ? tr( "°" ) : i >= 6 && r.parameterNames[i].size() < 3 ? tr( " px" ) : QString();
      lines << QStringLiteral( "%1 = %2 ± %3%4" ).arg( QString::fromStdString( r.parameterNames[i] ), -6 ).arg( r.estimates[i], 0, 'f', decimals ).arg( r.sigmas[i], 0, 'g', 3 ).arg( unit );
    }
  }
  mLayerInPhoto->setPhoto( mImageId, currentOrientation() );
  mDemCoverage.reset();
  if ( const geostation::Monoplotter *monoplotter = mLayerInPhoto->monoplotter() )
  {
    // 108 rays: a few milliseconds, so it follows every change
    mDemCoverage = geostation::demCoverageOfImage( *monoplotter );
    lines << tr( "DEM: %1" ).arg( QString::fromStdString( mDemCoverage->message ) );
  }
  mResultText->setPlainText( lines.join( QLatin1Char( '\n' ) ) );
  mSaveButton->setEnabled( summary.oriented() );
  drawMarkers();
}

void GeoStationOrientationDock::drawMarkers()
{
  mOverlay->draw( mMultiview, mImageId, *mModel );
}
