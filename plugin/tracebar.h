/***************************************************************************
  tracebar.h - the Multiview's Trace tool bar
  -------------------------------------------------------------------------
  The Trace toggle (while on, a click on a road line in a view traces it;
  a drag gives its direction), the progress of the running trace, and the
  line's state: stations, vertices, length, worst sigma, the last stop.
  Only shows the trace controller's state; the dock routes clicks and keys.
 ***************************************************************************/
#ifndef GEOSTATIONTRACEBAR_H
#define GEOSTATIONTRACEBAR_H

#include <QToolBar>

class QAction;
class QLabel;
class QProgressBar;
class GeoStationTraceController;

class GeoStationTraceBar : public QToolBar
{
    Q_OBJECT

  public:
    GeoStationTraceBar( GeoStationTraceController *controller, QWidget *parent = nullptr );

    bool isTracing() const;
    void setTracing( bool on );
    QString statusText() const;

  signals:
    void tracingToggled( bool on );

  private:
    void updateStatus();

    GeoStationTraceController *mController;
    QAction *mActionTrace = nullptr;
    QProgressBar *mProgress = nullptr;
    QLabel *mStatus = nullptr;
};

#endif // GEOSTATIONTRACEBAR_H
