/***************************************************************************
  backgroundtask.cpp - one long core call off the GUI thread
 ***************************************************************************/
#include "backgroundtask.h"

#include <exception>

#include <QtConcurrent/QtConcurrentRun>

GeoStationBackgroundTask::GeoStationBackgroundTask( QObject *parent )
  : QObject( parent )
{
  connect( &mWatcher, &QFutureWatcher<QString>::finished, this, [this]
  {
    mRunning = false;
    if ( mButton )
    {
      mButton->setText( mIdleText );
      mButton->setToolTip( mIdleTip );
    }
    emit finished( mWatcher.result() );
  } );
}

GeoStationBackgroundTask::~GeoStationBackgroundTask()
{
  mCancel->store( true );
  mWatcher.disconnect( this );
  mWatcher.waitForFinished();
}

bool GeoStationBackgroundTask::start( Work work )
{
  if ( mRunning )
    return false;
  mCancel = std::make_shared<std::atomic<bool>>( false );
  const geostation::Progress progress( [self = QPointer<GeoStationBackgroundTask>( this )]( double fraction, const std::string &text )
  {
    const QString what = QString::fromStdString( text );
    QMetaObject::invokeMethod( self, [self, fraction, what] { if ( self ) emit self->progressChanged( fraction, what ); }, Qt::QueuedConnection );
  }, [cancel = mCancel] { return cancel->load(); } );
  mRunning = true;
  if ( mButton )
  {
    mButton->setText( mRunningText );
    mButton->setToolTip( mRunningTip );
  }
  mWatcher.setFuture( QtConcurrent::run( [work = std::move( work ), progress]() -> QString
  {
    try
    {
      work( progress );
    }
    catch ( const std::exception &e )
    {
      return QString::fromStdString( e.what() );
    }
    return QString();
  } ) );
  return true;
}

void GeoStationBackgroundTask::cancel()
{
  mCancel->store( true );
}

void GeoStationBackgroundTask::attachButton( QAbstractButton *button, const std::function<void()> &start, const QString &runningText, const QString &runningTip )
{
  mButton = button;
  mIdleText = button->text();
  mIdleTip = button->toolTip();
  mRunningText = runningText;
  mRunningTip = runningTip;
  connect( button, &QAbstractButton::clicked, this, [this, start]
  {
    if ( mRunning )
      cancel();
    else
      start();
  } );
}
