/***************************************************************************
  tracecontroller.cpp
 ***************************************************************************/
#include "tracecontroller.h"

#include <chrono>
#include <cmath>

#include <QDateTime>
#include <QPointer>
#include <QUuid>
#include <QtConcurrent/QtConcurrentRun>

#include "multiviewsession.h"

namespace
{
  qint64 nowNs()
  {
    return std::chrono::duration_cast<std::chrono::nanoseconds>( std::chrono::steady_clock::now().time_since_epoch() ).count();
  }
}

GeoStationTraceController::GeoStationTraceController( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QObject *parent )
  : QObject( parent )
  , mSession( session )
  , mStore( store )
{
  connect( &mWatcher, &QFutureWatcher<geostation::RoadTraceSummary>::finished, this, &GeoStationTraceController::traceFinished );
  // another block: a line of the old one means nothing there
  connect( mSession, &GeoStationMultiviewSession::blockChanged, this, [this]
  {
    if ( mRunning )
    {
      // its result belongs to the old block: not taken
      mCancel->store( true );
      mWatcher.waitForFinished();
      mRunning = false;
      emit runningChanged( false );
    }
    if ( !mLine.empty() )
      emit message( tr( "The traced line of %n vertex(es) was dropped: another block was opened.", nullptr, static_cast<int>( mLine.vertices().size() ) ), true );
    mLine.clear();
    mLive.clear();
    emit lineChanged();
  } );
}

GeoStationTraceController::~GeoStationTraceController()
{
  mCancel->store( true );
  mWatcher.waitForFinished();
}

bool GeoStationTraceController::start( const QString &imageId, const QPointF &pixelInImage, std::optional<double> directionDeg )
{
  if ( isRunning() )
  {
    emit message( tr( "Tracing is running: wait for it or press Esc to stop it." ), true );
    return false;
  }
  const geostation::Block *block = mSession->block();
  if ( !block )
  {
    emit message( tr( "Open a block to trace in (GeoStation ▸ Open Block…)." ), true );
    return false;
  }
  const GeoStationFeatureClass *featureClass = mSession->findClass( mSession->currentClass() );
  if ( !featureClass || featureClass->geometry != GeoStationFeatureClass::Geometry::Line )
  {
    emit message( tr( "Choose a line class to trace into (GeoStation ▸ Feature Classes… to define one)." ), true );
    return false;
  }
  if ( !mSession->orientedImage( imageId ) )
  {
    emit message( tr( "%1 is not oriented: tracing needs oriented images." ).arg( imageId ), true );
    return false;
  }

  geostation::TraceSeed seed;
  seed.id = QUuid::createUuid().toString( QUuid::WithoutBraces ).toStdString();
  seed.imageId = imageId.toStdString();
  seed.pixelInImage = Eigen::Vector2d( pixelInImage.x(), pixelInImage.y() );
  seed.directionDeg = directionDeg;

  geostation::RoadTraceOptions options = mOptions;
  options.cameraHeightM = mSession->cameraHeightAboveRoadM();
  mCancel = std::make_shared<std::atomic<bool>>( false );
  options.progress = geostation::Progress( [self = QPointer<GeoStationTraceController>( this )]( double fraction, const std::string &text )
  {
    const QString what = QString::fromStdString( text );
    QMetaObject::invokeMethod( self, [self, fraction, what] { if ( self ) emit self->progressChanged( fraction, what ); }, Qt::QueuedConnection );
  }, [cancel = mCancel] { return cancel->load(); } );
  options.stationTraced = [self = QPointer<GeoStationTraceController>( this )]( const geostation::TracedStation &station, const std::vector<Eigen::Vector2d> &,
                          const std::vector<Eigen::Vector2d> &, const std::vector<geostation::TracedVertex> &lineSoFar )
  {
    const qint64 sent = nowNs();
    QMetaObject::invokeMethod( self, [self, station, lineSoFar, sent] { if ( self ) self->stationArrived( station, lineSoFar, sent ); }, Qt::QueuedConnection );
  };

  // the trace works on its own copy of the block: the operator may open another meanwhile
  auto blockCopy = std::make_shared<const geostation::Block>( *block );
  mLive = mLine;
  mStationsTraced = 0;
  mLastStop.clear();
  mLastStopMessage.clear();
  emit message( tr( "Tracing from %1 (%2, %3)%4…" ).arg( imageId ).arg( pixelInImage.x(), 0, 'f', 1 ).arg( pixelInImage.y(), 0, 'f', 1 )
                .arg( mLine.empty() ? QString() : tr( ", continuing the line" ) ), false );
  mWatcher.setFuture( QtConcurrent::run( [blockCopy, seed, options]
  {
    try
    {
      return geostation::traceRoadLine( *blockCopy, seed, options, geostation::fileGreyImageSource( *blockCopy ) );
    }
    catch ( const std::exception &e )
    {
      geostation::RoadTraceSummary failed;
      failed.stop = geostation::TraceStop::NoEdge;
      failed.message = e.what();
      return failed;
    }
  } ) );
  mRunning = true;
  emit runningChanged( true );
  return true;
}

void GeoStationTraceController::stationArrived( const geostation::TracedStation &station, const std::vector<geostation::TracedVertex> &lineSoFar, qint64 sentNs )
{
  if ( !mRunning )
    return; // a late part of a trace whose result has been taken
  mLastStationDelayMs = ( nowNs() - sentNs ) / 1e6;
  ++mStationsTraced;
  mLive = mLine;
  mLive.append( lineSoFar );
  QString text = tr( "Station %1: %2, %3 px followed, %4 vertices" )
                 .arg( QString::fromStdString( station.stationId ), QString::fromStdString( geostation::traceMethodName( station.method ) ) )
                 .arg( station.pixelsFollowed ).arg( station.vertices );
  if ( !station.partnerMessage.empty() )
    text += QStringLiteral( " (%1)" ).arg( QString::fromStdString( station.partnerMessage ) );
  emit message( text, !station.partnerMessage.empty() );
  emit lineChanged();
}

void GeoStationTraceController::traceFinished()
{
  if ( !mRunning )
    return; // dropped with its block
  const geostation::RoadTraceSummary summary = mWatcher.result();
  mRunning = false;
  const size_t joined = mLine.append( summary );
  mLive = mLine;
  mLastStop = QString::fromStdString( geostation::traceStopName( summary.stop ) );
  mLastStopMessage = QString::fromStdString( summary.message );
  const bool needsOperator = summary.stop != geostation::TraceStop::EndOfRun && summary.stop != geostation::TraceStop::MaxStations;
  emit message( tr( "Tracing stopped (%1): %2. %3 vertices joined the line, now %4 vertices, %5 m." )
                .arg( mLastStop, mLastStopMessage ).arg( joined ).arg( mLine.vertices().size() ).arg( mLine.lengthM(), 0, 'f', 1 ), needsOperator );
  if ( !mLine.empty() )
    emit message( tr( "Click the line to continue, Backspace takes back the last station's part, F finishes, Esc drops the line." ), false );
  emit runningChanged( false );
  emit lineChanged();
  emit stopped( mLastStop, mLastStopMessage );
}

void GeoStationTraceController::cancel()
{
  if ( isRunning() )
  {
    mCancel->store( true );
    emit message( tr( "Stopping after the current station…" ), false );
  }
}

void GeoStationTraceController::takeBackStation()
{
  if ( isRunning() )
    return;
  const std::string station = mLine.takeBackLastStation();
  if ( station.empty() )
    return;
  mLive = mLine;
  emit message( tr( "Station %1's part taken back; the line has %2 vertices." ).arg( QString::fromStdString( station ) ).arg( mLine.vertices().size() ), false );
  emit lineChanged();
}

void GeoStationTraceController::discard()
{
  if ( isRunning() || mLine.empty() )
    return;
  emit message( tr( "Traced line of %1 vertices dropped." ).arg( mLine.vertices().size() ), false );
  mLine.clear();
  mLive.clear();
  emit lineChanged();
}

GeoStationMeasuredFeature GeoStationTraceController::feature( const QString &className ) const
{
  GeoStationMeasuredFeature f;
  f.className = className;
  f.featureMethod = QStringLiteral( "traced" );
  const std::vector<geostation::TracedVertex> &vertices = mLine.vertices();
  if ( !vertices.empty() && !vertices.front().imageIds.empty() )
  {
    const QString reference = QString::fromStdString( vertices.front().imageIds.front() );
    f.station = mSession->imageStation( reference );
    f.acquired = mSession->imageTime( reference );
  }
  for ( const geostation::TracedVertex &t : vertices )
  {
    geostation::MeasuredVertex v;
    v.status = geostation::MeasuredVertex::Status::Ok;
    v.method = geostation::VertexMethod::Intersection;
    v.point = t.point;
    v.sigmaM = t.sigmaM;
    v.imageIds = t.imageIds;
    v.residualsPx = t.residualsPx;
    v.rangeM = t.rangeM;
    double sum = 0.0;
    for ( const Eigen::Vector2d &r : t.residualsPx )
      sum += r.squaredNorm();
    v.rmsPx = t.residualsPx.empty() ? 0.0 : std::sqrt( sum / t.residualsPx.size() );
    // the angle between the two rays at the vertex
    std::vector<Eigen::Vector3d> rays;
    for ( const std::string &id : t.imageIds )
      if ( const geostation::OrientedImage *image = mSession->orientedImage( QString::fromStdString( id ) ) )
        rays.push_back( ( t.point - image->exterior().projectionCentre ).normalized() );
    if ( rays.size() == 2 )
      v.maxRayAngleDeg = std::acos( std::clamp( rays[0].dot( rays[1] ), -1.0, 1.0 ) ) * 180.0 / M_PI;
    f.vertices << v;
  }
  return f;
}

bool GeoStationTraceController::finish()
{
  if ( isRunning() )
  {
    emit message( tr( "Tracing is running: press Esc to stop it, then finish." ), true );
    return false;
  }
  const GeoStationFeatureClass *featureClass = mSession->findClass( mSession->currentClass() );
  if ( !featureClass || featureClass->geometry != GeoStationFeatureClass::Geometry::Line )
  {
    emit message( tr( "Choose a line class to write the traced line into." ), true );
    return false;
  }
  if ( mLine.vertices().size() < 2 )
  {
    emit message( tr( "The traced line has %n vertex(es); a line needs 2.", nullptr, static_cast<int>( mLine.vertices().size() ) ), true );
    return false;
  }
  GeoStationMeasuredFeature f = feature( featureClass->name );
  f.measured = QDateTime::currentDateTimeUtc().toString( Qt::ISODateWithMs );
  f.measurementId = QUuid::createUuid().toString( QUuid::WithoutBraces );
  const GeoStationMeasurementStore::Result result = mStore->addFeature( f );
  emit message( tr( "%1 (traced, %2 vertices, %3 m, %4 stations, σ max %5 m): %6" )
                .arg( featureClass->name ).arg( f.vertices.size() ).arg( mLine.lengthM(), 0, 'f', 1 ).arg( mLine.stationIds().size() )
                .arg( mLine.sigmaMaxM(), 0, 'f', 3 ).arg( result.message ), !result.committed );
  if ( !result.ok )
    return false; // kept: the operator can fix the problem and finish again
  mLine.clear();
  mLive.clear();
  emit lineChanged();
  emit featureWritten( featureClass->layerName() );
  return true;
}
