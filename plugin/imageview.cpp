/***************************************************************************
  imageview.cpp
 ***************************************************************************/
#include "imageview.h"

#include <QComboBox>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QLabel>
#include <QStackedWidget>
#include <QVBoxLayout>

#include <qgsmapcanvas.h>
#include <qgsrasterdataprovider.h>
#include <qgsrasterlayer.h>
#include <qgsrubberband.h>
#include <qgsvertexmarker.h>

#include "imagepointtool.h"
#include "imageproc/enhancement.h"
#include "io/photoimport.h"
#include "io/rasterfile.h"

GeoStationImageView::GeoStationImageView( int index, QWidget *parent )
  : QWidget( parent )
  , mIndex( index )
{
  setObjectName( QStringLiteral( "mGeoStationImageView%1" ).arg( index ) );
  QVBoxLayout *layout = new QVBoxLayout( this );
  layout->setContentsMargins( 0, 0, 0, 0 );
  layout->setSpacing( 2 );
  QHBoxLayout *header = new QHBoxLayout();
  mImageCombo = new QComboBox( this );
  mImageCombo->setObjectName( QStringLiteral( "mImageCombo" ) );
  mImageCombo->setToolTip( tr( "Image shown in this view (any image of the block)" ) );
  mImageCombo->setSizeAdjustPolicy( QComboBox::AdjustToContents );
  mEnhancementCombo = new QComboBox( this );
  mEnhancementCombo->setObjectName( QStringLiteral( "mEnhancementCombo" ) );
  mEnhancementCombo->setToolTip( tr( "Enhancement, computed for viewing only" ) );
  mEnhancementCombo->setSizeAdjustPolicy( QComboBox::AdjustToContents );
  for ( const auto &choice : enhancementChoices() )
    mEnhancementCombo->addItem( choice.second, choice.first );
  mStatus = new QLabel( this );
  mStatus->setObjectName( QStringLiteral( "mStatus" ) );
  header->addWidget( mImageCombo );
  header->addWidget( mEnhancementCombo );
  header->addWidget( mStatus, 1 );
  layout->addLayout( header );

  mStack = new QStackedWidget( this );
  mCanvas = new QgsMapCanvas( mStack );
  mCanvas->setObjectName( QStringLiteral( "mGeoStationViewCanvas%1" ).arg( index ) );
  mCanvas->setCanvasColor( QColor( 40, 40, 40 ) );
  mCanvas->setDestinationCrs( QgsCoordinateReferenceSystem() );
  mCanvas->setParallelRenderingEnabled( true );
  mCanvas->setCachingEnabled( true );
  mCanvas->setPreviewJobsEnabled( false );
  mPlaceholder = new QLabel( mStack );
  mPlaceholder->setObjectName( QStringLiteral( "mPlaceholder" ) );
  mPlaceholder->setAlignment( Qt::AlignCenter );
  mPlaceholder->setWordWrap( true );
  mStack->addWidget( mCanvas );
  mStack->addWidget( mPlaceholder );
  layout->addWidget( mStack, 1 );

  mTool = new GeoStationImagePointTool( mCanvas );
  mCanvas->setMapTool( mTool );
  connect( mTool, &GeoStationImagePointTool::pixelPicked, this, [this]( QPointF p ) { emit pixelPicked( mIndex, p ); } );
  connect( mTool, &GeoStationImagePointTool::pixelDragged, this, [this]( QPointF from, QPointF to ) { emit pixelDragged( mIndex, from, to ); } );
  connect( mTool, &GeoStationImagePointTool::pixelHovered, this, [this]( QPointF p ) { emit pixelHovered( mIndex, p ); } );
  connect( mTool, &GeoStationImagePointTool::undoRequested, this, &GeoStationImageView::undoRequested );
  connect( mImageCombo, qOverload<int>( &QComboBox::activated ), this, [this]( int )
  {
    emit imageChosen( mIndex, mImageCombo->currentText() );
  } );
  connect( mEnhancementCombo, qOverload<int>( &QComboBox::activated ), this, [this]( int )
  {
    setEnhancement( mEnhancementCombo->currentData().toString() );
    emit enhancementChosen( mIndex, mEnhancement );
  } );

  mEpipolar = new QgsRubberBand( mCanvas, QgsWkbTypes::LineGeometry );
  mEpipolar->setStrokeColor( QColor( 0, 220, 255, 220 ) );
  mEpipolar->setWidth( 1 );
  mOverlayLines = new QgsRubberBand( mCanvas, QgsWkbTypes::LineGeometry );
  mOverlayLines->setStrokeColor( QColor( 255, 200, 0, 230 ) );
  mOverlayLines->setWidth( 2 );
  mTraceOverlay = new QgsRubberBand( mCanvas, QgsWkbTypes::LineGeometry );
  mTraceOverlay->setStrokeColor( QColor( 0, 220, 255, 240 ) );
  mTraceOverlay->setWidth( 3 );
  mOldCourse = new QgsRubberBand( mCanvas, QgsWkbTypes::LineGeometry );
  mOldCourse->setStrokeColor( QColor( 255, 60, 60, 230 ) );
  mOldCourse->setLineStyle( Qt::DashLine );
  mOldCourse->setWidth( 2 );
  mNewCourse = new QgsRubberBand( mCanvas, QgsWkbTypes::LineGeometry );
  mNewCourse->setStrokeColor( QColor( 40, 230, 40, 240 ) );
  mNewCourse->setWidth( 3 );
  mOverlayPoints = new QgsRubberBand( mCanvas, QgsWkbTypes::PointGeometry );
  mOverlayPoints->setStrokeColor( QColor( 255, 200, 0, 230 ) );
  mOverlayPoints->setIcon( QgsRubberBand::ICON_CIRCLE );
  mOverlayPoints->setIconSize( 9 );
  mOverlayPoints->setWidth( 2 );
  mProposal = new QgsVertexMarker( mCanvas );
  mProposal->setIconType( QgsVertexMarker::ICON_BOX );
  mProposal->setIconSize( 14 );
  mProposal->setPenWidth( 2 );
  mProposal->setColor( QColor( 40, 255, 40 ) );
  mProposal->hide();
  mObservation = new QgsVertexMarker( mCanvas );
  mObservation->setIconType( QgsVertexMarker::ICON_CROSS );
  mObservation->setIconSize( 18 );
  mObservation->setPenWidth( 2 );
  mObservation->setColor( QColor( 255, 40, 40 ) );
  mObservation->hide();
  showPlaceholder( tr( "No image" ) );
}

GeoStationImageView::~GeoStationImageView()
{
  mCanvas->setLayers( {} );
  mLayer.reset();
  geostation::discardMemoryRaster( mMemoryPath.toStdString() );
}

QList<QPair<QString, QString>> GeoStationImageView::enhancementChoices()
{
  return { { QString(), tr( "Original" ) },
    { QStringLiteral( "linear" ), tr( "Linear stretch 1 %" ) },
    { QStringLiteral( "equalise" ), tr( "Equalise" ) },
    { QStringLiteral( "two_segment" ), tr( "Two-segment stretch" ) },
    { QStringLiteral( "three_segment" ), tr( "Three-segment stretch" ) },
    { QStringLiteral( "sobel_addback" ), tr( "Sharpen (Sobel add-back)" ) },
    { QStringLiteral( "difference_addback" ), tr( "Sharpen (difference add-back)" ) },
    { QStringLiteral( "box_filter" ), tr( "Adaptive box filter" ) } };
}

bool GeoStationImageView::hasImage() const
{
  return mStack->currentWidget() == mCanvas && mLayer;
}

QString GeoStationImageView::placeholderText() const
{
  return mStack->currentWidget() == mPlaceholder ? mPlaceholder->text() : QString();
}

void GeoStationImageView::setImageChoices( const QStringList &imageIds )
{
  const QString current = mImageCombo->currentText();
  mImageCombo->blockSignals( true );
  mImageCombo->clear();
  mImageCombo->addItems( imageIds );
  mImageCombo->setCurrentIndex( std::max( 0, imageIds.indexOf( mImageId.isEmpty() ? current : mImageId ) ) );
  mImageCombo->blockSignals( false );
}

void GeoStationImageView::showPlaceholder( const QString &reason )
{
  mCanvas->setLayers( {} );
  mLayer.reset();
  mPlaceholder->setText( reason );
  mStack->setCurrentWidget( mPlaceholder );
  clearMeasurementOverlays();
}

void GeoStationImageView::setStatus( const QString &text )
{
  mStatus->setText( text );
}

void GeoStationImageView::showImage( const QString &imageId, const QString &path, int expectedWidth, int expectedHeight )
{
  if ( imageId == mImageId && path == mPath && ( mLayer || imageId.isEmpty() ) )
    return;
  const bool sameSize = mLayer && expectedWidth == mWidth && expectedHeight == mHeight;
  mImageId = imageId;
  mPath = path;
  mWidth = expectedWidth;
  mHeight = expectedHeight;
  const int comboIndex = mImageCombo->findText( imageId );
  if ( comboIndex >= 0 )
    mImageCombo->setCurrentIndex( comboIndex );
  setStatus( imageId );
  clearMeasurementOverlays();
  if ( imageId.isEmpty() )
  {
    showPlaceholder( tr( "No image of this camera at this station." ) );
    return;
  }
  if ( !QFileInfo::exists( path ) )
  {
    showPlaceholder( tr( "%1: the file %2 does not exist." ).arg( imageId, path ) );
    return;
  }
  const QgsRectangle previousExtent = mCanvas->extent();
  updateLayer();
  if ( !mLayer )
    return;
  // a photo tagged to be shown turned (a camera held upright) or mirrored is shown so; its pixels, and every
  // measurement in them, stay as stored (updateLayer() gave a mirrored one the map x = -col)
  const int turn = geostation::viewForExifOrientation( mExifOrientation ).turnDeg;
  const bool sameTurn = turn == mTurnDeg && mMirrored == mLayerMirrored;
  mTurnDeg = turn;
  mMirrored = mLayerMirrored;
  mTool->setMirrored( mMirrored );
  mCanvas->setRotation( turn );
  if ( sameSize && sameTurn )
    mCanvas->setExtent( previousExtent );
  else
    zoomToFullImage();
  mCanvas->refresh();
}

void GeoStationImageView::updateLayer()
{
  // a photo with a world file or a georeferenced TIFF is drawn in its pixels all the same (x = col, y = -row);
  // the same opening gives its EXIF orientation
  const QString pixelsPath = QStringLiteral( "/vsimem/geostation/view%1/%2-pixels.vrt" ).arg( mIndex ).arg( mImageId );
  QString source = QString::fromStdString( geostation::pixelSpaceSource( mPath.toStdString(), pixelsPath.toStdString(), &mExifOrientation, true ) );
  const bool mirrored = source == pixelsPath && geostation::viewForExifOrientation( mExifOrientation ).mirrored;
  QString problem;
  if ( !mEnhancement.isEmpty() )
  {
    if ( source == pixelsPath )
      geostation::discardMemoryRaster( pixelsPath.toStdString() ); // the enhanced copy is in pixel space already
    // the enhanced copy lives in GDAL's memory files, never on disk
    try
    {
      const geostation::RasterImage original = geostation::readRaster( mPath.toStdString() );
      geostation::EnhancementOptions options;
      options.method = *geostation::enhancementMethodFromName( mEnhancement.toStdString() );
      if ( options.method == geostation::EnhancementMethod::LinearStretch )
        options.clipPercent = 1.0;
      const cv::Mat enhanced = geostation::enhanceImage( original.pixels, options );
      const QString memoryPath = QStringLiteral( "/vsimem/geostation/view%1/%2-%3.tif" ).arg( mIndex ).arg( mImageId, mEnhancement );
      geostation::RasterImage like; // pixel space, mirrored as the original's VRT was
      if ( mirrored )
        like.geoTransform = std::array<double, 6> { 0.0, -1.0, 0.0, 0.0, 0.0, -1.0 };
      geostation::writeGeoTiffLike( memoryPath.toStdString(), enhanced, like );
      source = memoryPath;
    }
    catch ( const std::exception &e )
    {
      problem = QString::fromStdString( e.what() );
    }
  }
  QgsRasterLayer::LayerOptions options;
  options.skipCrsValidation = true;
  std::unique_ptr<QgsRasterLayer> layer;
  if ( problem.isEmpty() )
  {
    layer = std::make_unique<QgsRasterLayer>( source, mImageId, QStringLiteral( "gdal" ), options );
    if ( !layer->isValid() )
      problem = tr( "the file cannot be decoded (%1)" ).arg( layer->error().summary().trimmed() );
    else if ( layer->width() != mWidth || layer->height() != mHeight )
      problem = tr( "it is %1 × %2 pixels, its camera says %3 × %4" ).arg( layer->width() ).arg( layer->height() ).arg( mWidth ).arg( mHeight );
  }
  if ( !problem.isEmpty() )
  {
    showPlaceholder( tr( "%1 cannot be shown: %2." ).arg( mImageId, problem ) );
    return;
  }
  layer->setCrs( QgsCoordinateReferenceSystem() );
  mLayerMirrored = mirrored;
  mCanvas->setLayers( { layer.get() } );
  std::swap( mLayer, layer );
  // the previous memory copy is freed once the canvas no longer uses it
  if ( mMemoryPath != source )
  {
    geostation::discardMemoryRaster( mMemoryPath.toStdString() );
    mMemoryPath = source.startsWith( QLatin1String( "/vsimem/" ) ) ? source : QString();
  }
  mStack->setCurrentWidget( mCanvas );
}

void GeoStationImageView::setEnhancement( const QString &method )
{
  if ( method == mEnhancement )
    return;
  if ( !method.isEmpty() && !geostation::enhancementMethodFromName( method.toStdString() ) )
    return;
  mEnhancement = method;
  const int i = mEnhancementCombo->findData( method );
  if ( i >= 0 )
    mEnhancementCombo->setCurrentIndex( i );
  if ( mLayer )
  {
    const QgsRectangle extent = mCanvas->extent();
    updateLayer();
    mCanvas->setExtent( extent );
    mCanvas->refresh();
  }
}

QgsPointXY GeoStationImageView::mapFromPixel( const QPointF &pixelInImage ) const
{
  return GeoStationImagePointTool::mapFromPixel( pixelInImage.x(), pixelInImage.y(), mMirrored );
}

QgsGeometry GeoStationImageView::inView( const QgsGeometry &pixelSpace ) const
{
  if ( !mMirrored || pixelSpace.isNull() )
    return pixelSpace;
  QgsGeometry mirrored = pixelSpace;
  mirrored.transform( QTransform::fromScale( -1.0, 1.0 ) );
  return mirrored;
}

QString GeoStationImageView::valueAt( const QPointF &pixelInImage ) const
{
  if ( !mLayer || pixelInImage.x() < 0 || pixelInImage.y() < 0 || pixelInImage.x() >= mWidth || pixelInImage.y() >= mHeight )
    return QString();
  QStringList values;
  for ( int band = 1; band <= mLayer->bandCount(); ++band )
  {
    bool ok = false;
    const double v = mLayer->dataProvider()->sample( mapFromPixel( pixelInImage ), band, &ok );
    values << ( ok ? QString::number( v ) : QStringLiteral( "–" ) );
  }
  return values.join( ',' );
}

void GeoStationImageView::zoomToPixel( const QPointF &pixelInImage, double halfWidthPx )
{
  const double aspect = mCanvas->height() > 0 ? static_cast<double>( mCanvas->height() ) / std::max( 1, mCanvas->width() ) : 0.75;
  const QgsPointXY centre = mapFromPixel( pixelInImage );
  mCanvas->setExtent( QgsRectangle( centre.x() - halfWidthPx, centre.y() - halfWidthPx * aspect, centre.x() + halfWidthPx, centre.y() + halfWidthPx * aspect ) );
  mCanvas->refresh();
}

void GeoStationImageView::zoomToFullImage()
{
  // the extent is the view's (turned with it): a photo shown turned a quarter lies across it
  const bool across = mTurnDeg == 90 || mTurnDeg == 270;
  const double halfWide = 0.5 * ( across ? mHeight : mWidth ), halfHigh = 0.5 * ( across ? mWidth : mHeight );
  const QgsPointXY centre = mapFromPixel( QPointF( 0.5 * mWidth, 0.5 * mHeight ) );
  mCanvas->setExtent( QgsRectangle( centre.x() - halfWide, centre.y() - halfHigh, centre.x() + halfWide, centre.y() + halfHigh ) );
  mCanvas->refresh();
}

void GeoStationImageView::setEpipolarCurves( const geostation::EpipolarCurve &curve )
{
  QVector<QgsGeometry> lines;
  for ( const auto &piece : curve.pieces )
  {
    if ( piece.size() < 2 )
      continue;
    QgsPolylineXY line;
    for ( const geostation::EpipolarVertex &v : piece )
      line << GeoStationImagePointTool::mapFromPixel( v.pixelInImage.x(), v.pixelInImage.y(), mMirrored );
    lines << QgsGeometry::fromPolylineXY( line );
  }
  if ( lines.isEmpty() )
    mEpipolar->reset( QgsWkbTypes::LineGeometry );
  else
    mEpipolar->setToGeometry( QgsGeometry::collectGeometry( lines ) );
}

void GeoStationImageView::setProposal( bool matched, const QPointF &pixelInImage, double score, const QString &status, bool doubtful )
{
  if ( matched )
  {
    mProposal->setCenter( mapFromPixel( pixelInImage ) );
    // a correlation peak only: a red cross, for the operator to confirm
    mProposal->setIconType( doubtful ? QgsVertexMarker::ICON_X : QgsVertexMarker::ICON_BOX );
    mProposal->setColor( doubtful ? QColor( 255, 40, 40 ) : score >= 0.8 ? QColor( 40, 255, 40 ) : QColor( 255, 160, 0 ) );
    mProposal->show();
  }
  else
    mProposal->hide();
  setStatus( status.isEmpty() ? mImageId : QStringLiteral( "%1 · %2" ).arg( mImageId, status ) );
}

void GeoStationImageView::setObservation( bool present, const QPointF &pixelInImage, bool reference )
{
  if ( !present )
  {
    mObservation->hide();
    return;
  }
  mObservation->setCenter( mapFromPixel( pixelInImage ) );
  mObservation->setColor( reference ? QColor( 255, 40, 40 ) : QColor( 255, 40, 255 ) );
  mObservation->show();
}

void GeoStationImageView::clearMeasurementOverlays()
{
  mEpipolar->reset( QgsWkbTypes::LineGeometry );
  mProposal->hide();
  mObservation->hide();
  setStatus( mImageId );
}

void GeoStationImageView::setFeatureOverlay( const QVector<QgsGeometry> &geometries )
{
  QVector<QgsGeometry> points, lines;
  for ( const QgsGeometry &g : geometries )
    if ( !g.isNull() )
      ( g.type() == QgsWkbTypes::PointGeometry ? points : lines ) << inView( g );
  mFeatureOverlayCount = points.size() + lines.size();
  // setToGeometry() also makes the band's geometry type right, and redraws it
  if ( lines.isEmpty() )
    mOverlayLines->reset( QgsWkbTypes::LineGeometry );
  else
    mOverlayLines->setToGeometry( QgsGeometry::collectGeometry( lines ) );
  if ( points.isEmpty() )
    mOverlayPoints->reset( QgsWkbTypes::PointGeometry );
  else
    mOverlayPoints->setToGeometry( QgsGeometry::collectGeometry( points ) );
}

void GeoStationImageView::setTraceOverlay( const QgsGeometry &geometry )
{
  mTraceOverlayVertices = geometry.isNull() ? 0 : geometry.constGet()->nCoordinates();
  if ( geometry.isNull() )
    mTraceOverlay->reset( QgsWkbTypes::LineGeometry );
  else
    mTraceOverlay->setToGeometry( inView( geometry ) );
}

void GeoStationImageView::setChangeOverlay( const QgsGeometry &oldCourse, const QgsGeometry &newCourse )
{
  const auto draw = [this]( QgsRubberBand *band, const QgsGeometry &course )
  {
    if ( course.isNull() )
    {
      band->reset( QgsWkbTypes::LineGeometry );
      return 0;
    }
    band->setToGeometry( inView( course ) );
    return course.constGet()->nCoordinates();
  };
  mChangeOverlayVertices = qMakePair( draw( mOldCourse, oldCourse ), draw( mNewCourse, newCourse ) );
}
