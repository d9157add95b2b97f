/***************************************************************************
  multiviewdock.cpp
 ***************************************************************************/
#include "multiviewdock.h"

#include <cmath>
#include <limits>

#include <QComboBox>
#include <QGridLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QMainWindow>
#include <QPlainTextEdit>
#include <QKeyEvent>
#include <QSpinBox>
#include <QSplitter>
#include <QTabWidget>
#include <QTimer>
#include <QToolBar>
#include <QToolButton>
#include <QVBoxLayout>

#include <qgscoordinatereferencesystem.h>
#include <qgsgeometry.h>
#include <qgsmapcanvas.h>

#include "geometry/imagespace.h"
#include "camerapanel.h"
#include "changeinimages.h"
#include "imageview.h"
#include "measurementcontroller.h"
#include "measurementoverlay.h"
#include "measurementstore.h"
#include "multiviewsession.h"
#include "tracebar.h"
#include "tracecontroller.h"
#include "tracing/linetrace.h"

GeoStationMultiviewDock::GeoStationMultiviewDock( GeoStationMultiviewSession *session, GeoStationMeasurementController *controller, GeoStationMeasurementStore *store,
    QWidget *parent, GeoStationTraceController *trace )
  : QgsDockWidget( tr( "GeoStation Multiview" ), parent )
  , mSession( session )
  , mController( controller )
  , mStore( store )
  , mTrace( trace )
{
  setObjectName( QStringLiteral( "GeoStationMultiviewDock" ) );
  QWidget *contents = new QWidget( this );
  QVBoxLayout *layout = new QVBoxLayout( contents );
  layout->setContentsMargins( 2, 2, 2, 2 );
  layout->addWidget( buildToolbar() );
  layout->addWidget( buildMeasureBar() );
  if ( mTrace )
  {
    mTraceBar = new GeoStationTraceBar( mTrace, contents );
    layout->addWidget( mTraceBar );
    // tracing and point measuring share the clicks: the open point (not the feature) goes
    connect( mTraceBar, &GeoStationTraceBar::tracingToggled, mController, &GeoStationMeasurementController::viewsChanged );
    connect( mTrace, &GeoStationTraceController::lineChanged, this, &GeoStationMultiviewDock::updateTraceOverlays );
    connect( mTrace, &GeoStationTraceController::message, this, &GeoStationMultiviewDock::appendMessage );
  }

  QSplitter *splitter = new QSplitter( Qt::Vertical, contents );
  mViewArea = new QWidget( splitter );
  mGrid = new QGridLayout( mViewArea );
  mGrid->setContentsMargins( 0, 0, 0, 0 );
  mGrid->setSpacing( 3 );
  QTabWidget *panels = new QTabWidget( splitter );
  mMessages = new QPlainTextEdit( panels );
  mMessages->setObjectName( QStringLiteral( "mMessages" ) );
  mMessages->setReadOnly( true );
  mMessages->setMaximumBlockCount( 2000 );
  panels->addTab( mMessages, tr( "Messages" ) );
  mCameraTable = new GeoStationCameraPanel( panels );
  panels->addTab( mCameraTable, tr( "Cameras" ) );
  splitter->addWidget( mViewArea );
  splitter->addWidget( panels );
  splitter->setStretchFactor( 0, 4 );
  splitter->setStretchFactor( 1, 1 );
  layout->addWidget( splitter, 1 );
  mCursorLabel = new QLabel( contents );
  mCursorLabel->setObjectName( QStringLiteral( "mCursorLabel" ) );
  layout->addWidget( mCursorLabel );
  setWidget( contents );

  mOverlayTimer = new QTimer( this );
  mOverlayTimer->setSingleShot( true );
  mOverlayTimer->setInterval( 30 );
  connect( mOverlayTimer, &QTimer::timeout, this, &GeoStationMultiviewDock::updateFeatureOverlays );

  connect( mSession, &GeoStationMultiviewSession::blockChanged, this, &GeoStationMultiviewDock::rebuildViews );
  connect( mSession, &GeoStationMultiviewSession::stationChanged, this, [this]
  {
    mNavigationTimer.start();
    updateStationControls();
  } );
  connect( mSession, &GeoStationMultiviewSession::viewImagesChanged, this, &GeoStationMultiviewDock::showViewImages );
  connect( mSession, &GeoStationMultiviewSession::featureClassesChanged, this, &GeoStationMultiviewDock::updateClassCombo );
  connect( mController, &GeoStationMeasurementController::viewStatesChanged, this, &GeoStationMultiviewDock::updateMeasurementOverlays );
  connect( mController, &GeoStationMeasurementController::featureChanged, this, &GeoStationMultiviewDock::updateFeatureStatus );
  connect( mController, &GeoStationMeasurementController::message, this, &GeoStationMultiviewDock::appendMessage );
  // the block file rewritten on disk (an adjustment, an import): the views show the new orientations, the operator is told
  connect( mSession, &GeoStationMultiviewSession::blockReloaded, this, [this]( const QString &summary )
  {
    rebuildViews();
    appendMessage( summary, false );
  } );
  connect( mSession, &GeoStationMultiviewSession::blockFileProblem, this, [this]( const QString &problem ) { appendMessage( problem, true ); } );
  connect( mStore, &GeoStationMeasurementStore::measurementsChanged, this, &GeoStationMultiviewDock::scheduleFeatureOverlays );

  rebuildViews();
  updateClassCombo();
  updateFeatureStatus();
}

GeoStationMultiviewDock::~GeoStationMultiviewDock()
{
  for ( const QPointer<QgsDockWidget> &dock : std::as_const( mViewDocks ) )
    delete dock;
}

bool GeoStationMultiviewDock::tracing() const
{
  return mTraceBar && mTraceBar->isTracing();
}

void GeoStationMultiviewDock::picked( int view, const QPointF &from, const std::optional<QPointF> &to )
{
  const GeoStationImageView *v = mViews.value( view );
  if ( mPickingRedirected )
  {
    if ( v )
      emit imagePixelPicked( v->imageId(), to ? *to : from );
    return;
  }
  if ( tracing() && v )
  {
    // a drag gives the line's direction
    std::optional<double> directionDeg;
    if ( to )
      directionDeg = geostation::degreesFromDirection( Eigen::Vector2d( to->x() - from.x(), to->y() - from.y() ) );
    mTrace->start( v->imageId(), from, directionDeg );
    return;
  }
  mProposalTimer.start();
  mController->pick( view, to ? *to : from );
}

std::function<void()> GeoStationMultiviewDock::keyAction( int key, Qt::KeyboardModifiers modifiers )
{
  const bool ctrl = modifiers & Qt::ControlModifier;
  if ( modifiers & ~( Qt::ControlModifier | Qt::KeypadModifier ) )
    return nullptr;
  if ( tracing() )
    switch ( key )
    {
      case Qt::Key_Escape:
        return [this] { mTrace->isRunning() ? mTrace->cancel() : mTrace->discard(); };
      case Qt::Key_Backspace:
        return [this] { mTrace->takeBackStation(); };
      case Qt::Key_F:
        return ctrl ? nullptr : std::function<void()>( [this] { mTrace->finish(); } );
      case Qt::Key_Return:
      case Qt::Key_Enter:
        return [] {};
    }
  switch ( key )
  {
    case Qt::Key_PageDown:
      return [this, ctrl] { stepStations( ctrl ? 10 : 1 ); };
    case Qt::Key_PageUp:
      return [this, ctrl] { stepStations( ctrl ? -10 : -1 ); };
    case Qt::Key_Home:
      return [this] { firstStation(); };
    case Qt::Key_End:
      return [this] { lastStation(); };
    case Qt::Key_Return:
    case Qt::Key_Enter:
      return [this] { mController->acceptPoint(); };
    case Qt::Key_Backspace:
      return [this] { mController->undoVertex(); };
    case Qt::Key_F:
      return ctrl ? nullptr : std::function<void()>( [this] { mController->finishFeature(); } );
    case Qt::Key_Escape:
      return [this] { mController->cancel(); };
  }
  return nullptr;
}

bool GeoStationMultiviewDock::eventFilter( QObject *watched, QEvent *event )
{
  if ( event->type() == QEvent::ShortcutOverride || event->type() == QEvent::KeyPress )
  {
    QKeyEvent *keyEvent = static_cast<QKeyEvent *>( event );
    if ( const std::function<void()> action = keyAction( keyEvent->key(), keyEvent->modifiers() ) )
    {
      if ( event->type() == QEvent::ShortcutOverride )
        event->accept(); // the key comes to us, not to a QGIS shortcut
      else
        action();
      return true;
    }
  }
  return QgsDockWidget::eventFilter( watched, event );
}

QWidget *GeoStationMultiviewDock::buildToolbar()
{
  QToolBar *bar = new QToolBar( this );
  bar->setObjectName( QStringLiteral( "mNavigationBar" ) );
  bar->setIconSize( QSize( 16, 16 ) );
  const auto add = [&]( const QString &name, const QString &text, const QString &tip, const std::function<void()> &slot )
  {
    QAction *a = bar->addAction( text );
    a->setObjectName( name );
    a->setToolTip( tip );
    connect( a, &QAction::triggered, this, slot );
  };
  add( QStringLiteral( "mActionFirstStation" ), QStringLiteral( "|◀" ), tr( "First station (Home)" ), [this] { firstStation(); } );
  add( QStringLiteral( "mActionBack10" ), QStringLiteral( "◀◀" ), tr( "10 stations back (Ctrl+PgUp)" ), [this] { stepStations( -10 ); } );
  add( QStringLiteral( "mActionPreviousStation" ), QStringLiteral( "◀" ), tr( "Previous station (PgUp)" ), [this] { previousStation(); } );
  mStationCombo = new QComboBox( bar );
  mStationCombo->setObjectName( QStringLiteral( "mStationCombo" ) );
  mStationCombo->setEditable( true );
  mStationCombo->setInsertPolicy( QComboBox::NoInsert );
  mStationCombo->setMinimumContentsLength( 18 );
  mStationCombo->setToolTip( tr( "Station: choose one, or type a station id or a time (ISO 8601)" ) );
  bar->addWidget( mStationCombo );
  connect( mStationCombo, qOverload<int>( &QComboBox::activated ), this, [this]( int index )
  {
    if ( mStationCombo->itemText( index ) == mStationCombo->currentText() && index < mSession->run().size() )
      mSession->setCurrentStation( index );
  } );
  connect( mStationCombo->lineEdit(), &QLineEdit::returnPressed, this, [this]
  {
    if ( !goToStation( mStationCombo->currentText().section( ' ', 0, 0 ) ) )
      appendMessage( tr( "No station %1 (give a station id or an ISO 8601 time)." ).arg( mStationCombo->currentText() ), true );
  } );
  add( QStringLiteral( "mActionNextStation" ), QStringLiteral( "▶" ), tr( "Next station (PgDown)" ), [this] { nextStation(); } );
  add( QStringLiteral( "mActionForward10" ), QStringLiteral( "▶▶" ), tr( "10 stations forward (Ctrl+PgDown)" ), [this] { stepStations( 10 ); } );
  add( QStringLiteral( "mActionLastStation" ), QStringLiteral( "▶|" ), tr( "Last station (End)" ), [this] { lastStation(); } );
  bar->addSeparator();
  bar->addWidget( new QLabel( tr( "Views" ), bar ) );
  mViewCountSpin = new QSpinBox( bar );
  mViewCountSpin->setObjectName( QStringLiteral( "mViewCountSpin" ) );
  mViewCountSpin->setRange( 1, GeoStationMultiviewSession::sMaxViews );
  bar->addWidget( mViewCountSpin );
  connect( mViewCountSpin, qOverload<int>( &QSpinBox::valueChanged ), this, [this]( int n ) { mSession->setViewCount( n ); } );
  QAction *separate = bar->addAction( tr( "Separate docks" ) );
  separate->setObjectName( QStringLiteral( "mActionSeparateDocks" ) );
  separate->setCheckable( true );
  separate->setToolTip( tr( "Each view in a dock of its own, or all in the grid" ) );
  connect( separate, &QAction::toggled, this, &GeoStationMultiviewDock::setSeparateDocks );
  return bar;
}

QWidget *GeoStationMultiviewDock::buildMeasureBar()
{
  QToolBar *bar = new QToolBar( this );
  bar->setObjectName( QStringLiteral( "mMeasureBar" ) );
  bar->addWidget( new QLabel( tr( "Measure" ), bar ) );
  mClassCombo = new QComboBox( bar );
  mClassCombo->setObjectName( QStringLiteral( "mClassCombo" ) );
  mClassCombo->setMinimumContentsLength( 12 );
  bar->addWidget( mClassCombo );
  connect( mClassCombo, qOverload<int>( &QComboBox::activated ), this, [this]( int ) { mSession->setCurrentClass( mClassCombo->currentData().toString() ); } );
  const auto add = [&]( const QString &name, const QString &text, const QString &tip, const std::function<void()> &slot )
  {
    QAction *a = bar->addAction( text );
    a->setObjectName( name );
    a->setToolTip( tip );
    connect( a, &QAction::triggered, this, slot );
  };
  add( QStringLiteral( "mActionAcceptPoint" ), tr( "Accept" ), tr( "Intersect the rays of the point and add the vertex (Return)" ), [this] { mController->acceptPoint(); } );
  add( QStringLiteral( "mActionUndoVertex" ), tr( "Undo" ), tr( "Take back the open point, then the last vertex (Backspace, right click)" ), [this] { mController->undoVertex(); } );
  add( QStringLiteral( "mActionFinishFeature" ), tr( "Finish" ), tr( "Write the line or polygon to its layer (F)" ), [this] { mController->finishFeature(); } );
  add( QStringLiteral( "mActionCancelFeature" ), tr( "Cancel" ), tr( "Drop the feature being measured (Escape)" ), [this] { mController->cancel(); } );
  mFeatureStatus = new QLabel( bar );
  mFeatureStatus->setObjectName( QStringLiteral( "mFeatureStatus" ) );
  bar->addWidget( mFeatureStatus );
  return bar;
}

void GeoStationMultiviewDock::rebuildViews()
{
  const int wanted = std::max( 1, mSession->viewCount() );
  while ( mViews.size() > wanted )
    delete mViews.takeLast();
  while ( mViews.size() < wanted )
  {
    GeoStationImageView *view = new GeoStationImageView( mViews.size(), mViewArea );
    connect( view, &GeoStationImageView::pixelPicked, this, [this]( int index, QPointF p ) { picked( index, p, std::nullopt ); } );
    connect( view, &GeoStationImageView::pixelDragged, this, [this]( int index, QPointF from, QPointF to ) { picked( index, from, to ); } );
    connect( view, &GeoStationImageView::pixelHovered, this, [this]( int index, QPointF p )
    {
      const GeoStationImageView *v = mViews.value( index );
      if ( v )
        mCursorLabel->setText( tr( "%1   col %2   row %3   value %4" ).arg( v->imageId() ).arg( p.x(), 0, 'f', 1 ).arg( p.y(), 0, 'f', 1 ).arg( v->valueAt( p ) ) );
    } );
    connect( view, &GeoStationImageView::imageChosen, this, [this]( int index, const QString &id ) { mSession->setViewImage( index, id ); } );
    connect( view, &GeoStationImageView::undoRequested, this, [this] { tracing() ? mTrace->takeBackStation() : mController->undoVertex(); } );
    connect( view->canvas(), &QgsMapCanvas::mapCanvasRefreshed, this, &GeoStationMultiviewDock::viewRefreshed );
    view->canvas()->installEventFilter( this );
    mViews << view;
  }
  QStringList ids;
  if ( mSession->block() )
    for ( const geostation::BlockImage &image : mSession->block()->images )
      ids << QString::fromStdString( image.id );
  for ( GeoStationImageView *view : std::as_const( mViews ) )
    view->setImageChoices( ids );
  layoutViews();
  mViewCountSpin->blockSignals( true );
  mViewCountSpin->setValue( wanted );
  mViewCountSpin->blockSignals( false );
  updateStationControls();
  showViewImages();
}

void GeoStationMultiviewDock::layoutViews()
{
  for ( const QPointer<QgsDockWidget> &dock : std::as_const( mViewDocks ) )
    if ( dock )
    {
      dock->setWidget( nullptr );
      delete dock;
    }
  mViewDocks.clear();
  const int n = mViews.size();
  const int columns = n <= 3 ? n : ( n + 1 ) / 2;
  QMainWindow *window = qobject_cast<QMainWindow *>( parentWidget() );
  for ( int i = 0; i < n; ++i )
  {
    GeoStationImageView *view = mViews[i];
    if ( mSeparateDocks && window )
    {
      QgsDockWidget *dock = new QgsDockWidget( tr( "GeoStation view %1" ).arg( i + 1 ), window );
      dock->setObjectName( QStringLiteral( "GeoStationViewDock%1" ).arg( i ) );
      dock->setWidget( view );
      window->addDockWidget( Qt::RightDockWidgetArea, dock );
      mViewDocks << dock;
    }
    else
    {
      view->setParent( mViewArea );
      mGrid->addWidget( view, i / columns, i % columns );
      view->show();
    }
  }
}

void GeoStationMultiviewDock::setSeparateDocks( bool separate )
{
  if ( separate == mSeparateDocks )
    return;
  // take the views back out of their docks before those are deleted
  for ( GeoStationImageView *view : std::as_const( mViews ) )
  {
    view->setParent( mViewArea );
    mGrid->removeWidget( view );
  }
  mSeparateDocks = separate;
  layoutViews();
}

void GeoStationMultiviewDock::showViewImages()
{
  if ( mViews.size() != mSession->viewCount() )
  {
    rebuildViews();
    return;
  }
  const QStringList ids = mSession->viewImages();
  const geostation::Block *block = mSession->block();
  mPendingRefreshes = 0;
  QStringList shown;
  for ( int i = 0; i < mViews.size(); ++i )
  {
    const QString id = ids.value( i );
    const geostation::BlockImage *image = block && !id.isEmpty() ? block->findImage( id.toStdString() ) : nullptr;
    if ( !image )
    {
      mViews[i]->showImage( QString(), QString(), 0, 0 );
      continue;
    }
    const geostation::Camera &camera = block->cameraOf( *image );
    const QString before = mViews[i]->imageId();
    mViews[i]->showImage( id, mSession->imagePath( id ), camera.width, camera.height );
    if ( mViews[i]->hasImage() && before != id )
      ++mPendingRefreshes;
    shown << id;
  }
  if ( mPendingRefreshes == 0 )
  {
    mLastNavigationMs = mNavigationTimer.isValid() ? mNavigationTimer.nsecsElapsed() / 1e6 : 0.0;
    emit stationShown( mLastNavigationMs );
  }
  mController->viewsChanged();
  // the images shown and the next station's are prepared for matching meanwhile (those of stations passed are dropped)
  QStringList toPrepare = shown;
  if ( mSession->currentStation() >= 0 )
  {
    const int n = mSession->run().stepped( mSession->currentStation(), 1 );
    for ( const std::string &id : mSession->run().at( n ).imageIds )
      toPrepare << QString::fromStdString( id );
  }
  mController->prefetch( toPrepare );
  updateCameraPanel();
  scheduleFeatureOverlays();
  updateTraceOverlays();
}

void GeoStationMultiviewDock::updateTraceOverlays()
{
  if ( !mTrace )
    return;
  const std::vector<Eigen::Vector3d> points = mTrace->line().points();
  for ( GeoStationImageView *view : std::as_const( mViews ) )
  {
    const geostation::OrientedImage *image = mSession->orientedImage( view->imageId() );
    view->setTraceOverlay( image && view->hasImage() && points.size() >= 2 ? projectPolylineIntoImage( points, *image ) : QgsGeometry() );
  }
}

void GeoStationMultiviewDock::viewRefreshed()
{
  if ( mPendingRefreshes <= 0 )
    return;
  if ( --mPendingRefreshes == 0 && mNavigationTimer.isValid() )
  {
    mLastNavigationMs = mNavigationTimer.nsecsElapsed() / 1e6;
    emit stationShown( mLastNavigationMs );
  }
}

void GeoStationMultiviewDock::updateStationControls()
{
  const geostation::StationSequence &run = mSession->run();
  mStationCombo->blockSignals( true );
  if ( mStationCombo->count() != run.size() )
  {
    mStationCombo->clear();
    for ( const geostation::SequenceStation &s : run.stations() )
      mStationCombo->addItem( QStringLiteral( "%1 %2" ).arg( QString::fromStdString( s.id ), QString::fromStdString( s.time ) ).trimmed() );
  }
  mStationCombo->setCurrentIndex( mSession->currentStation() );
  mStationCombo->blockSignals( false );
  setWindowTitle( mSession->currentStation() >= 0 ? tr( "GeoStation Multiview — station %1 (%2 of %3)" ).arg( mSession->currentStationId() ).arg( mSession->currentStation() + 1 ).arg( run.size() )
                  : tr( "GeoStation Multiview" ) );
}

void GeoStationMultiviewDock::updateMeasurementOverlays()
{
  const QVector<GeoStationMeasurementController::ViewState> &states = mController->viewStates();
  for ( int i = 0; i < mViews.size(); ++i )
  {
    if ( i >= states.size() || states[i].imageId != mViews[i]->imageId() )
    {
      mViews[i]->clearMeasurementOverlays();
      continue;
    }
    const GeoStationMeasurementController::ViewState &s = states[i];
    mViews[i]->setEpipolarCurves( s.curve );
    mViews[i]->setProposal( s.proposed && !s.corrected, s.pixel, s.score, s.status, s.doubtful );
    mViews[i]->setObservation( s.observed && ( s.reference || s.corrected ), s.pixel, s.reference );
  }
  if ( mProposalTimer.isValid() && mController->hasOpenPoint() )
  {
    mLastProposalMs = mProposalTimer.nsecsElapsed() / 1e6;
    mProposalTimer.invalidate();
  }
}

void GeoStationMultiviewDock::scheduleFeatureOverlays()
{
  mOverlayTimer->start();
}

void GeoStationMultiviewDock::updateFeatureOverlays()
{
  const geostation::Block *block = mSession->block();
  if ( !block )
    return;
  const QgsCoordinateReferenceSystem &crs = mSession->crs();
  const QList<QgsVectorLayer *> layers = mStore->measurementLayers();
  for ( GeoStationImageView *view : std::as_const( mViews ) )
  {
    const geostation::OrientedImage *image = mSession->orientedImage( view->imageId() );
    view->setFeatureOverlay( image && view->hasImage() ? projectFeaturesIntoImage( layers, *image, crs ) : QVector<QgsGeometry>() );
  }
}

void GeoStationMultiviewDock::updateCameraPanel()
{
  mCameraTable->showImages( mSession->block(), mSession->viewImages() );
}

void GeoStationMultiviewDock::updateClassCombo()
{
  mClassCombo->clear();
  for ( const GeoStationFeatureClass &c : mSession->featureClasses() )
    mClassCombo->addItem( QStringLiteral( "%1 (%2)" ).arg( c.name, GeoStationFeatureClass::geometryName( c.geometry ) ), c.name );
  mClassCombo->setCurrentIndex( mClassCombo->findData( mSession->currentClass() ) );
  updateFeatureStatus();
}

void GeoStationMultiviewDock::updateFeatureStatus()
{
  const int n = mController->vertexCount();
  mFeatureStatus->setText( mSession->featureClasses().isEmpty() ? tr( "no feature classes yet" ) : n == 0 ? tr( "click a point in a view" ) : tr( "%n vertex(es)", nullptr, n ) );
}

void GeoStationMultiviewDock::appendMessage( const QString &text, bool warning )
{
  mMessages->appendHtml( warning ? QStringLiteral( "<span style=\"color:#c00\">%1</span>" ).arg( text.toHtmlEscaped() ) : text.toHtmlEscaped() );
}

QString GeoStationMultiviewDock::messagesText() const
{
  return mMessages->toPlainText();
}

QWidget *GeoStationMultiviewDock::viewWidget( int index ) const
{
  return mViews.value( index );
}

void GeoStationMultiviewDock::zoomViewToPixel( int view, double col, double row, double halfWidthPx )
{
  if ( GeoStationImageView *v = mViews.value( view ) )
    v->zoomToPixel( QPointF( col, row ), halfWidthPx );
}

bool GeoStationMultiviewDock::setViewImage( int view, const QString &imageId )
{
  return mSession->setViewImage( view, imageId );
}

void GeoStationMultiviewDock::showChange( const QgsGeometry &oldCourse, const QgsGeometry &newCourse, const QgsCoordinateReferenceSystem &crs )
{
  const geostation::Block *block = mSession->block();
  if ( !block )
    return;
  // heights: the map's where it has them, else the new course's mean (a 2-D map on the measured ground)
  const std::vector<Eigen::Vector3d> newPoints = courseInBlockCrs( newCourse, crs, mSession->crs(), std::nan( "" ) );
  const std::vector<Eigen::Vector3d> oldPoints = courseInBlockCrs( oldCourse, crs, mSession->crs(), meanHeight( newPoints ).value_or( 0.0 ) );
  const std::vector<Eigen::Vector3d> &shown = newPoints.size() >= 2 ? newPoints : oldPoints;
  if ( shown.size() < 2 )
  {
    for ( GeoStationImageView *view : std::as_const( mViews ) )
      view->setChangeOverlay( QgsGeometry(), QgsGeometry() );
    return;
  }
  const Eigen::Vector3d middle = shown[shown.size() / 2];

  // the views that do not see it get the images that see it best, each image once
  QStringList ids;
  for ( const geostation::BlockImage &image : block->images )
    ids << QString::fromStdString( image.id );
  const auto oriented = [this]( const QString &id ) { return mSession->orientedImage( id ); };
  const QStringList seeing = imagesSeeing( middle, ids, oriented );
  QStringList shownIds = mSession->viewImages();
  QStringList candidates;
  for ( const QString &id : seeing )
    if ( !shownIds.contains( id ) )
      candidates << id;
  for ( int v = 0; v < mViews.size(); ++v )
    if ( !seeing.contains( shownIds.value( v ) ) && !candidates.isEmpty() )
      mSession->setViewImage( v, candidates.takeFirst() );

  GeoStationOverlayOptions options;
  options.maxRangeM = std::numeric_limits<double>::infinity(); // aerial images see far
  for ( GeoStationImageView *view : std::as_const( mViews ) )
  {
    const geostation::OrientedImage *image = mSession->orientedImage( view->imageId() );
    if ( !image || !view->hasImage() )
    {
      view->setChangeOverlay( QgsGeometry(), QgsGeometry() );
      continue;
    }
    const QgsGeometry oldInImage = oldPoints.size() >= 2 ? projectPolylineIntoImage( oldPoints, *image, options ) : QgsGeometry();
    const QgsGeometry newInImage = newPoints.size() >= 2 ? projectPolylineIntoImage( newPoints, *image, options ) : QgsGeometry();
    view->setChangeOverlay( oldInImage, newInImage );
    const QgsGeometry extent = newInImage.isNull() ? oldInImage : newInImage;
    if ( !extent.isNull() )
    {
      const QgsRectangle box = extent.boundingBox(); // in image space
      const Eigen::Vector2d centre = geostation::pixelOfImageSpace( Eigen::Vector2d( box.center().x(), box.center().y() ) );
      view->zoomToPixel( QPointF( centre.x(), centre.y() ), 0.6 * std::max( box.width(), box.height() ) + 40.0 );
    }
  }
}

void GeoStationMultiviewDock::setViewEnhancement( int view, const QString &method )
{
  if ( GeoStationImageView *v = mViews.value( view ) )
    v->setEnhancement( method );
}

void GeoStationMultiviewDock::firstStation()
{
  mSession->setCurrentStation( 0 );
}

void GeoStationMultiviewDock::lastStation()
{
  mSession->setCurrentStation( mSession->run().size() - 1 );
}

void GeoStationMultiviewDock::nextStation()
{
  mSession->stepStation( 1 );
}

void GeoStationMultiviewDock::previousStation()
{
  mSession->stepStation( -1 );
}

void GeoStationMultiviewDock::stepStations( int step )
{
  mSession->stepStation( step );
}

bool GeoStationMultiviewDock::goToStation( const QString &idOrTime )
{
  const int index = mSession->run().indexOfIdOrTime( idOrTime.trimmed().toStdString() );
  if ( index < 0 )
    return false;
  mSession->setCurrentStation( index );
  return true;
}
