/***************************************************************************
  backgroundtask.h - one long core call off the GUI thread
  -------------------------------------------------------------------------
  The docks' long one-shot operations (Identify Automatically, fiducial
  detection) run on a worker thread: the work gets a geostation::Progress
  that reports to the GUI thread (progressChanged) and stops when cancel()
  is asked; its end is signalled on the GUI thread (finished), an
  exception from core as its sentence. The work writes its result into
  what it captured (a shared pointer the caller keeps). No maths here.
 ***************************************************************************/
#ifndef GEOSTATIONBACKGROUNDTASK_H
#define GEOSTATIONBACKGROUNDTASK_H

#include <atomic>
#include <functional>
#include <memory>

#include <QFutureWatcher>
#include <QAbstractButton>
#include <QObject>
#include <QPointer>
#include <QString>

#include "progress/progress.h"

class GeoStationBackgroundTask : public QObject
{
    Q_OBJECT

  public:
    //! Runs on the worker thread; returns nothing, or throws (std::exception: its sentence is passed on).
    using Work = std::function<void( const geostation::Progress &progress )>;

    explicit GeoStationBackgroundTask( QObject *parent = nullptr );
    //! Asks running work to stop and waits for it (its end is not signalled).
    ~GeoStationBackgroundTask() override;

    bool isRunning() const { return mRunning; }
    //! Starts `work`; false while other work runs.
    bool start( Work work );
    //! Asks the running work to stop (its Progress says so); it ends soon after.
    void cancel();

    /**
     * The dock's button for the work: a click calls `start` when idle and
     * cancel() while the work runs; meanwhile the button reads `runningText`
     * (with `runningTip`), and its own text and tooltip again once it ends.
     */
    void attachButton( QAbstractButton *button, const std::function<void()> &start, const QString &runningText, const QString &runningTip );

  signals:
    void progressChanged( double fraction, const QString &text );
    //! The work has ended: `error` is the sentence of what it threw, else empty.
    void finished( const QString &error );

  private:
    QFutureWatcher<QString> mWatcher;
    std::shared_ptr<std::atomic<bool>> mCancel = std::make_shared<std::atomic<bool>>( false );
    bool mRunning = false;
    QPointer<QAbstractButton> mButton;
    QString mIdleText, mIdleTip, mRunningText, mRunningTip;
};

#endif // GEOSTATIONBACKGROUNDTASK_H
