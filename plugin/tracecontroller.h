/***************************************************************************
  tracecontroller.h - the Multiview's Trace tool: one click, the run traced
  -------------------------------------------------------------------------
  start() takes the operator's click on a road line in a view (with a
  direction when the click was a drag) and runs core traceRoadLine() on a
  pool thread, on a copy of the block, so QGIS stays responsive. After
  every station the line so far comes back to the GUI thread
  (lineChanged()), to be drawn in the views and on the Overview map as it
  grows. cancel() (Esc) stops tracing after the current station; what was
  traced is kept.

  Where tracing stops, stopped() says why in one sentence and the
  operator chooses: click the line again to continue (the new trace joins
  the line, core TracedLine), takeBackStation() to drop the last
  station's part, finish() to write one LineStringZ into the current
  class layer through the edit buffer (method "traced", the vertices table
  filled), or discard(). A feature that cannot be written stays here.
  No widgets; the dock wires it to the views.
 ***************************************************************************/
#ifndef GEOSTATIONTRACECONTROLLER_H
#define GEOSTATIONTRACECONTROLLER_H

#include <atomic>
#include <memory>
#include <optional>

#include <QFutureWatcher>
#include <QObject>
#include <QPointF>

#include "measurementstore.h"
#include "tracing/roadtracer.h"
#include "tracing/tracedline.h"

class GeoStationMultiviewSession;

class GeoStationTraceController : public QObject
{
    Q_OBJECT

  public:
    GeoStationTraceController( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QObject *parent = nullptr );
    //! Cancels a running trace and waits for it (at most one station).
    ~GeoStationTraceController() override;

    bool isRunning() const { return mRunning; }
    //! The line: every part traced so far, with the running trace's stations as they come.
    const geostation::TracedLine &line() const { return mLive; }
    //! The last stop: its reason name (e.g. "gap_too_large") and sentence; empty while none.
    QString lastStop() const { return mLastStop; }
    QString lastStopMessage() const { return mLastStopMessage; }
    //! Stations traced by the running (or last) trace.
    int stationsTraced() const { return mStationsTraced; }
    //! Milliseconds from the last station's end to its part on the GUI thread (the live-drawing delay).
    double lastStationDelayMs() const { return mLastStationDelayMs; }

    //! What the tool runs with (method, ranges, stripe sigma floor); the camera height comes from the session.
    geostation::RoadTraceOptions &options() { return mOptions; }

    /**
     * Traces from a click in `imageId`; `directionDeg` (0 = up the image,
     * clockwise) when the operator dragged along the line. With a line
     * already traced, the new trace continues it. False (with a message)
     * when it cannot start: no block, no line class, a trace running, an
     * unknown or unoriented image.
     */
    bool start( const QString &imageId, const QPointF &pixelInImage, std::optional<double> directionDeg = std::nullopt );

  public slots:
    //! Stops the running trace after its current station (Esc); what was traced is kept.
    void cancel();
    //! Drops the last station's part of the line (not while tracing).
    void takeBackStation();
    //! Writes the line into the current class layer; false (and the line kept) when it cannot.
    bool finish();
    //! Drops the line (not while tracing).
    void discard();

  signals:
    void lineChanged();
    void progressChanged( double fraction, const QString &text );
    void runningChanged( bool running );
    //! Tracing ended: the stop reason's name and its sentence.
    void stopped( const QString &reason, const QString &message );
    //! One line for the message panel.
    void message( const QString &text, bool warning );
    void featureWritten( const QString &layerName );

  private:
    void stationArrived( const geostation::TracedStation &station, const std::vector<geostation::TracedVertex> &lineSoFar, qint64 sentNs );
    void traceFinished();
    //! The line as a feature for the store (vertices with their images, residuals and ray angles).
    GeoStationMeasuredFeature feature( const QString &className ) const;

    GeoStationMultiviewSession *mSession;
    GeoStationMeasurementStore *mStore;
    geostation::RoadTraceOptions mOptions;
    geostation::TracedLine mLine;      //!< finished parts
    geostation::TracedLine mLive;      //!< finished parts + the running trace so far
    std::shared_ptr<std::atomic<bool>> mCancel = std::make_shared<std::atomic<bool>>( false );
    QFutureWatcher<geostation::RoadTraceSummary> mWatcher;
    QString mLastStop, mLastStopMessage;
    int mStationsTraced = 0;
    bool mRunning = false; //!< from start() until the result is taken (the future finishes earlier, with stations still queued)
    double mLastStationDelayMs = 0.0;
};

#endif // GEOSTATIONTRACECONTROLLER_H
