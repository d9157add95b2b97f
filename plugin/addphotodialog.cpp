/***************************************************************************
  addphotodialog.cpp - GeoStation > Add Photo...: a photo and its camera
 ***************************************************************************/
#include "addphotodialog.h"

#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QPushButton>

#include "io/block.h"
#include "io/photoimport.h"
#include "multiviewsession.h"

GeoStationAddPhotoDialog::GeoStationAddPhotoDialog( const geostation::Block *block, const QgsCoordinateReferenceSystem &defaultCrs, QWidget *parent )
  : QDialog( parent )
  , mBlock( block )
{
  setupUi( this );
  mPhotoWidget->setStorageMode( QgsFileWidget::GetFile );
  mPhotoWidget->setFilter( tr( "Images (*.tif *.tiff *.jpg *.jpeg *.png *.jp2 *.bmp);;All files (*)" ) );
  mBlockWidget->setStorageMode( QgsFileWidget::SaveFile );
  mBlockWidget->setFilter( tr( "GeoStation block (*.geostation.json)" ) );
  mCrsWidget->setCrs( defaultCrs );
  mNewBlockGroup->setVisible( !block );
  connect( mPhotoWidget, &QgsFileWidget::fileChanged, this, &GeoStationAddPhotoDialog::photoChanged );
  connect( mCameraCombo, qOverload<int>( &QComboBox::currentIndexChanged ), this, &GeoStationAddPhotoDialog::cameraChoiceChanged );
  connect( mButtonBox, &QDialogButtonBox::accepted, this, &GeoStationAddPhotoDialog::accept );
  connect( mButtonBox, &QDialogButtonBox::rejected, this, &GeoStationAddPhotoDialog::reject );
  photoChanged();
}

QString GeoStationAddPhotoDialog::photoPath() const
{
  return mPhotoWidget->filePath();
}

void GeoStationAddPhotoDialog::setPhotoPath( const QString &path )
{
  mPhotoWidget->setFilePath( path );
  photoChanged();
}

QString GeoStationAddPhotoDialog::newBlockPath() const
{
  return mBlockWidget->filePath();
}

QgsCoordinateReferenceSystem GeoStationAddPhotoDialog::crs() const
{
  return mCrsWidget->crs();
}

QString GeoStationAddPhotoDialog::problem() const
{
  return mProblemLabel->text();
}

void GeoStationAddPhotoDialog::photoChanged()
{
  mProblemLabel->clear();
  mCameraCombo->blockSignals( true );
  mCameraCombo->clear();
  mPhotoWidth = mPhotoHeight = 0;
  const QString path = photoPath();
  if ( !path.isEmpty() )
  {
    try
    {
      const geostation::PhotoFileCamera guess = geostation::cameraFromPhotoFile( path.toStdString(), "camera" );
      mPhotoWidth = guess.camera.width;
      mPhotoHeight = guess.camera.height;
      // the block's cameras of this size first: a series of photos shares its camera
      if ( mBlock )
        for ( const geostation::Camera &c : mBlock->cameras )
          if ( c.width == mPhotoWidth && c.height == mPhotoHeight )
            mCameraCombo->addItem( tr( "%1 (of the block)" ).arg( QString::fromStdString( c.id ) ), QString::fromStdString( c.id ) );
      QString id = QFileInfo( path ).completeBaseName();
      for ( int n = 2; mBlock && mBlock->findCamera( id.toStdString() ); ++n )
        id = QStringLiteral( "%1_%2" ).arg( QFileInfo( path ).completeBaseName() ).arg( n );
      mIdEdit->setText( id );
      mFSpin->setValue( guess.camera.f );
      mCxSpin->setValue( guess.camera.cx );
      mCySpin->setValue( guess.camera.cy );
      mFocalNote->setText( guess.focalSource == "normal_lens_default"
                           ? tr( "%1 × %2 px. The file has no focal length: a normal lens (the diagonal) is assumed; give the calibrated value if you know it." ).arg( mPhotoWidth ).arg( mPhotoHeight )
                           : tr( "%1 × %2 px. Principal distance from the file's EXIF (%3)." ).arg( mPhotoWidth ).arg( mPhotoHeight ).arg( QString::fromStdString( guess.focalSource ) ) );
      if ( !guess.orientationNote().empty() )
      {
        QString note = QString::fromStdString( guess.orientationNote() );
        note[0] = note[0].toUpper();
        mFocalNote->setText( mFocalNote->text() + QLatin1Char( ' ' ) + note + QLatin1Char( '.' ) );
      }
      if ( !mBlock )
        mBlockWidget->setFilePath( QFileInfo( path ).absoluteDir().filePath( QFileInfo( path ).completeBaseName() + QStringLiteral( ".geostation.json" ) ) );
    }
    catch ( const std::exception &e )
    {
      mProblemLabel->setText( QString::fromStdString( e.what() ) );
    }
  }
  mCameraCombo->addItem( tr( "New camera" ), QString() );
  mCameraCombo->blockSignals( false );
  cameraChoiceChanged();
}

void GeoStationAddPhotoDialog::cameraChoiceChanged()
{
  mNewCameraGroup->setEnabled( mCameraCombo->currentData().toString().isEmpty() );
}

bool GeoStationAddPhotoDialog::camera( geostation::Camera *camera, QString *error ) const
{
  const QString existing = mCameraCombo->currentData().toString();
  if ( !existing.isEmpty() && mBlock )
  {
    *camera = mBlock->camera( existing.toStdString() );
    return true;
  }
  if ( mPhotoWidth <= 0 )
  {
    *error = tr( "Choose a photo that can be read." );
    return false;
  }
  QJsonObject json { { "id", mIdEdit->text().trimmed() }, { "width", mPhotoWidth }, { "height", mPhotoHeight }, { "f", mFSpin->value() }, { "cx", mCxSpin->value() },
    { "cy", mCySpin->value() } };
  if ( mPixelSpin->value() > 0.0 )
    json.insert( QStringLiteral( "pixel_size_mm" ), mPixelSpin->value() );
  if ( mDistortionCombo->currentText() != QLatin1String( "none" ) )
  {
    const QStringList values = mDistortionEdit->text().simplified().split( QLatin1Char( ' ' ), Qt::SkipEmptyParts );
    QJsonObject distortion { { "model", mDistortionCombo->currentText() } };
    const char *names[] = { "k1", "k2", "p1", "p2", "k3" };
    for ( int k = 0; k < values.size() && k < 5; ++k )
    {
      bool ok = false;
      distortion.insert( QString::fromLatin1( names[k] ), values[k].toDouble( &ok ) );
      if ( !ok )
      {
        *error = tr( "The lens distortion must read \"k1 k2 p1 p2 k3\" (numbers; the missing ones are 0)." );
        return false;
      }
    }
    if ( values.size() > 5 )
    {
      *error = tr( "The lens distortion has five coefficients: k1 k2 p1 p2 k3." );
      return false;
    }
    json.insert( QStringLiteral( "distortion" ), distortion );
  }
  QJsonArray fiducials;
  int lineNumber = 0;
  for ( const QString &line : mFiducialEdit->toPlainText().split( QLatin1Char( '\n' ) ) )
  {
    ++lineNumber;
    const QStringList parts = line.simplified().split( QLatin1Char( ' ' ), Qt::SkipEmptyParts );
    if ( parts.isEmpty() )
      continue;
    bool okX = false, okY = false;
    const double x = parts.value( 1 ).toDouble( &okX ), y = parts.value( 2 ).toDouble( &okY );
    if ( parts.size() != 3 || !okX || !okY )
    {
      *error = tr( "Fiducial line %1 must read \"id x_mm y_mm\"." ).arg( lineNumber );
      return false;
    }
    fiducials.append( QJsonObject { { "id", parts[0] }, { "x_mm", x }, { "y_mm", y } } );
  }
  if ( !fiducials.isEmpty() )
    json.insert( QStringLiteral( "fiducials" ), fiducials );
  try
  {
    *camera = geostation::cameraFromJsonText( QJsonDocument( json ).toJson( QJsonDocument::Compact ).toStdString() );
  }
  catch ( const std::exception &e )
  {
    *error = tr( "The camera is not valid: %1" ).arg( QString::fromStdString( e.what() ) );
    return false;
  }
  if ( !fiducials.isEmpty() && !camera->pixelSizeMm )
  {
    *error = tr( "A film camera with fiducials needs the scan's pixel size (mm)." );
    return false;
  }
  return true;
}

void GeoStationAddPhotoDialog::accept()
{
  geostation::Camera c;
  QString error;
  if ( photoPath().isEmpty() )
    error = tr( "Choose the photo." );
  else if ( !camera( &c, &error ) )
    ;
  else if ( !mBlock && newBlockPath().isEmpty() )
    error = tr( "Choose where the new block is saved." );
  else if ( !mBlock && ( !crs().isValid() || crs().isGeographic() ) )
    error = tr( "The new block needs a projected CRS in metres." );
  mProblemLabel->setText( error );
  if ( error.isEmpty() )
    QDialog::accept();
}

QString GeoStationAddPhotoDialog::addToBlock( GeoStationMultiviewSession *session, const QString &photoPath, const geostation::Camera &camera, const QString &newBlockPath,
    const QgsCoordinateReferenceSystem &crs, QString *error )
{
  const bool open = session->hasBlock();
  const QString blockPath = open ? session->blockPath() : newBlockPath;
  std::string imageId;
  try
  {
    if ( !open && ( !crs.isValid() || crs.isGeographic() ) )
      throw std::invalid_argument( tr( "the new block needs a projected CRS in metres" ).toStdString() );
    if ( !open && blockPath.isEmpty() )
      throw std::invalid_argument( tr( "the new block needs a file" ).toStdString() );
    const std::string crsText = crs.authid().isEmpty() ? crs.toWkt( QgsCoordinateReferenceSystem::WKT_PREFERRED ).toStdString() : crs.authid().toStdString();
    geostation::Block block = open ? *session->block() : geostation::newPhotoBlock( crsText, blockPath.toStdString() );
    imageId = geostation::addPhotoToBlock( block, photoPath.toStdString(), camera );
    block.save( blockPath.toStdString() );
  }
  catch ( const std::exception &e )
  {
    *error = tr( "%1 was not added: %2" ).arg( QFileInfo( photoPath ).fileName(), QString::fromStdString( e.what() ) );
    return QString();
  }
  if ( open ? !session->reloadBlock() : !session->openBlock( blockPath, error ) )
  {
    if ( error->isEmpty() )
      *error = tr( "%1 was added to %2, which cannot be read again now." ).arg( QFileInfo( photoPath ).fileName(), blockPath );
    return QString();
  }
  return QString::fromStdString( imageId );
}

bool GeoStationAddPhotoDialog::cameraForPhoto( const geostation::Block *block, const QString &photoPath, const QString &cameraJson, geostation::Camera *camera, QString *error )
{
  try
  {
    if ( !cameraJson.isEmpty() )
    {
      *camera = geostation::cameraFromJsonText( cameraJson.toStdString() );
      return true;
    }
    *camera = geostation::cameraFromPhotoFile( photoPath.toStdString(), QFileInfo( photoPath ).completeBaseName().toStdString() ).camera;
    if ( block )
      for ( const geostation::Camera &c : block->cameras )
        if ( c.width == camera->width && c.height == camera->height )
        {
          *camera = c;
          break;
        }
    return true;
  }
  catch ( const std::exception &e )
  {
    *error = tr( "%1 was not added: %2" ).arg( QFileInfo( photoPath ).fileName(), QString::fromStdString( e.what() ) );
    return false;
  }
}
