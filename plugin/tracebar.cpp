/***************************************************************************
  tracebar.cpp
 ***************************************************************************/
#include "tracebar.h"

#include <QAction>
#include <QLabel>
#include <QProgressBar>

#include "tracecontroller.h"

GeoStationTraceBar::GeoStationTraceBar( GeoStationTraceController *controller, QWidget *parent )
  : QToolBar( parent )
  , mController( controller )
{
  setObjectName( QStringLiteral( "mTraceBar" ) );
  mActionTrace = addAction( tr( "Trace" ) );
  mActionTrace->setObjectName( QStringLiteral( "mActionTrace" ) );
  mActionTrace->setCheckable( true );
  mActionTrace->setToolTip( tr( "Trace road lines: click on a lane marking, centre line or kerb (or drag along it) and it is followed "
                                "through the run. Esc stops; then click the line to continue, Backspace takes back the last station's "
                                "part, F writes the line into the current line class, Esc again drops it." ) );
  connect( mActionTrace, &QAction::toggled, this, &GeoStationTraceBar::tracingToggled );
  connect( mActionTrace, &QAction::toggled, this, &GeoStationTraceBar::updateStatus );
  QAction *stop = addAction( tr( "Stop" ) );
  stop->setObjectName( QStringLiteral( "mActionTraceStop" ) );
  stop->setToolTip( tr( "Stop tracing after the current station (Esc); what was traced is kept" ) );
  connect( stop, &QAction::triggered, mController, &GeoStationTraceController::cancel );
  QAction *back = addAction( tr( "Take back station" ) );
  back->setObjectName( QStringLiteral( "mActionTraceTakeBack" ) );
  back->setToolTip( tr( "Drop the last station's part of the traced line (Backspace)" ) );
  connect( back, &QAction::triggered, mController, &GeoStationTraceController::takeBackStation );
  QAction *finish = addAction( tr( "Finish line" ) );
  finish->setObjectName( QStringLiteral( "mActionTraceFinish" ) );
  finish->setToolTip( tr( "Write the traced line into the current line class (F)" ) );
  connect( finish, &QAction::triggered, mController, &GeoStationTraceController::finish );
  mProgress = new QProgressBar( this );
  mProgress->setObjectName( QStringLiteral( "mTraceProgress" ) );
  mProgress->setRange( 0, 1000 );
  mProgress->setMaximumWidth( 120 );
  mProgress->setVisible( false );
  addWidget( mProgress );
  mStatus = new QLabel( this );
  mStatus->setObjectName( QStringLiteral( "mTraceStatus" ) );
  addWidget( mStatus );

  connect( mController, &GeoStationTraceController::progressChanged, this, [this]( double fraction, const QString & )
  {
    mProgress->setValue( static_cast<int>( 1000 * fraction ) );
  } );
  connect( mController, &GeoStationTraceController::runningChanged, this, [this, stop, back, finish]( bool running )
  {
    mProgress->setVisible( running );
    mProgress->setValue( 0 );
    stop->setEnabled( running );
    back->setEnabled( !running );
    finish->setEnabled( !running );
    updateStatus();
  } );
  connect( mController, &GeoStationTraceController::lineChanged, this, &GeoStationTraceBar::updateStatus );
  stop->setEnabled( false );
  updateStatus();
}

bool GeoStationTraceBar::isTracing() const
{
  return mActionTrace->isChecked();
}

void GeoStationTraceBar::setTracing( bool on )
{
  mActionTrace->setChecked( on );
}

QString GeoStationTraceBar::statusText() const
{
  return mStatus->text();
}

void GeoStationTraceBar::updateStatus()
{
  const geostation::TracedLine &line = mController->line();
  QString text;
  if ( line.empty() && !mController->isRunning() )
    text = isTracing() ? tr( "click a road line" ) : QString();
  else
    text = tr( "%1 stations, %2 vertices, %3 m, σ max %4 m" )
           .arg( line.stationIds().size() ).arg( line.vertices().size() ).arg( line.lengthM(), 0, 'f', 1 ).arg( line.sigmaMaxM(), 0, 'f', 3 );
  if ( !mController->isRunning() && !mController->lastStop().isEmpty() && !line.empty() )
    text += tr( " — stopped: %1" ).arg( mController->lastStop() );
  mStatus->setText( text );
}
