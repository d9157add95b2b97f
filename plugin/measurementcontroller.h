/***************************************************************************
  measurementcontroller.h - the measuring loop of the Multiview
  -------------------------------------------------------------------------
  1. pick() in a view: the reference observation. The epipolar curves of
     the pixel in the other views and the proposed conjugate points (core
     proposeConjugates) are published for the views to draw.
  2. pick() in another view while a point is open: the operator's
     correction of that view's point (a click, or the end of a drag).
  3. acceptPoint(): the rays are intersected (two or more) with σ and pixel
     residuals; a point seen in one view only becomes a DEM vertex (when a
     DEM layer is set) or a road-plane vertex, marked by its method. The
     vertex joins the feature; a point class finishes it at once.
  4. undoVertex(), finishFeature(), cancel(). A feature that could not be
     written stays here (and in the edit buffer) — it is never dropped.
  No widgets; the dock connects it to the views.
 ***************************************************************************/
#ifndef GEOSTATIONMEASUREMENTCONTROLLER_H
#define GEOSTATIONMEASUREMENTCONTROLLER_H

#include <memory>

#include <QObject>
#include <QPointF>
#include <QVector>

#include "measurementstore.h"
#include "workstation/imageprefetcher.h"
#include "workstation/matchimagecache.h"
#include "workstation/pointmeasurer.h"

class GeoStationMultiviewSession;

namespace geostation
{
  class Dem;
  class CrsTransform;
}

class GeoStationMeasurementController : public QObject
{
    Q_OBJECT

  public:
    //! What a view shows of the point being measured.
    struct ViewState
    {
      QString imageId;
      bool observed = false;     //!< has an observation (reference, accepted proposal or correction)
      bool reference = false;
      bool corrected = false;    //!< set by the operator
      QPointF pixel;             //!< of the observation
      double sigmaPx = 0.5;
      bool proposed = false;     //!< a matched proposal exists
      bool doubtful = false;     //!< correlation only: drawn as such, not taken unless the operator confirms it
      double score = 0.0;
      QString status;            //!< short text for the view's header
      geostation::EpipolarCurve curve; //!< of the reference pixel in this view
    };

    GeoStationMeasurementController( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QObject *parent = nullptr );
    ~GeoStationMeasurementController() override;

    geostation::MatchImageCache &imageCache() { return *mCache; }
    /**
     * Prepares the images for matching in the background, in this order
     * (those of the station shown, then the next one's), instead of any
     * asked for earlier and not started.
     */
    void prefetch( const QStringList &imageIds );
    //! The background preparation's counts (core ImagePrefetcher).
    geostation::ImagePrefetcher::Summary prefetchSummary() const { return mPrefetcher.summary(); }

    void pick( int view, const QPointF &pixelInImage );
    bool hasOpenPoint() const { return mReference >= 0; }
    const QVector<ViewState> &viewStates() const { return mViews; }
    //! Milliseconds from the last reference pick to its curves and proposals.
    double lastProposalMs() const { return mLastProposalMs; }

    const GeoStationMeasuredFeature &currentFeature() const { return mFeature; }
    int vertexCount() const { return mFeature.vertices.size(); }
    const geostation::MeasuredVertex *lastVertex() const { return mFeature.vertices.isEmpty() ? nullptr : &mFeature.vertices.last(); }

    //! The proposal/matching settings (window, threshold, LSM, depth range).
    geostation::ProposalOptions &proposalOptions() { return mOptions; }

  public slots:
    bool acceptPoint();
    void undoVertex();
    bool finishFeature();
    void cancel();
    //! The views show other images (navigation): the open point is dropped, the feature kept.
    void viewsChanged();

  signals:
    void viewStatesChanged();
    void featureChanged();
    //! One line for the message panel.
    void message( const QString &text, bool warning );
    void featureWritten( const QString &layerName );

  private:
    geostation::MeasuredVertex singleRayVertex( const geostation::VertexObservation &observation, QString *why );
    //! The session's DEM layer, loaded once per source: false without one, or with `why` set when it cannot be used.
    bool loadDem( QString *why );
    void resetViews();

    GeoStationMultiviewSession *mSession;
    GeoStationMeasurementStore *mStore;
    std::shared_ptr<geostation::MatchImageCache> mCache = std::make_shared<geostation::MatchImageCache>();
    //! its thread loads into mCache; destroyed first, it waits for the load in progress
    geostation::ImagePrefetcher mPrefetcher { mCache };
    geostation::ProposalOptions mOptions;
    QVector<ViewState> mViews;
    int mReference = -1;
    double mLastProposalMs = 0.0;
    GeoStationMeasuredFeature mFeature;
    //! Per operator vertex: its image and pixel when it is a single-ray DEM vertex (else an empty id), and how many
    //! vertices densifying the line on the terrain were put before it (core demVerticesBetween()).
    struct OperatorVertex
    {
      QString demImageId;
      QPointF pixel;
      int densifiedBefore = 0;
    };
    QVector<OperatorVertex> mOperatorVertices;
    //! A line digitised in one image on the DEM gets a vertex on the terrain every this many pixels.
    static constexpr double sDensifyStepPx = 20.0;
    QString mDemPath;
    QString mDemError; //!< why the DEM at mDemPath cannot be used (empty: it can)
    std::unique_ptr<geostation::Dem> mDem;
    std::unique_ptr<geostation::CrsTransform> mBlockToDem;
};

#endif // GEOSTATIONMEASUREMENTCONTROLLER_H
