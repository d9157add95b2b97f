/***************************************************************************
  controlpointoverlay.cpp - the control points drawn in the photo's views
 ***************************************************************************/
#include "controlpointoverlay.h"

#include <qgsvertexmarker.h>

#include "controlpointmodel.h"
#include "imageview.h"
#include "multiviewdock.h"

GeoStationControlPointOverlay::~GeoStationControlPointOverlay()
{
  clear();
}

void GeoStationControlPointOverlay::clear()
{
  for ( const auto &[canvas, marker] : std::as_const( mMarkers ) )
    if ( canvas )
      delete marker;
  mMarkers.clear();
}

void GeoStationControlPointOverlay::draw( GeoStationMultiviewDock *multiview, const QString &imageId, const GeoStationControlPointModel &model )
{
  clear();
  if ( !multiview )
    return;
  for ( int v = 0; v < multiview->viewCount(); ++v )
  {
    GeoStationImageView *view = multiview->view( v );
    if ( !view || view->imageId() != imageId || !view->hasImage() )
      continue;
    const std::vector<geostation::PhotoControlPoint> &points = model.points();
    for ( size_t i = 0; i < points.size(); ++i )
    {
      const geostation::PhotoControlResult &result = model.summary().points[i];
      const auto offer = model.offers().find( points[i].pointId );
      std::optional<Eigen::Vector2d> pixel = points[i].pixelInFile;
      QColor colour = result.blunder ? QColor( 220, 0, 0 ) : QColor( 0, 200, 0 );
      int icon = QgsVertexMarker::ICON_CROSS;
      const bool offered = offer != model.offers().end()
                           && ( offer->second.status == geostation::PredictedPoint::Status::Found || offer->second.status == geostation::PredictedPoint::Status::Flagged );
      if ( !pixel && offered )
      {
        pixel = offer->second.pixelInFile;
        colour = offer->second.status == geostation::PredictedPoint::Status::Found ? QColor( 255, 160, 0 ) : QColor( 255, 60, 200 );
        icon = QgsVertexMarker::ICON_BOX;
      }
      else if ( !pixel && result.projectedInFile && result.inFrame )
      {
        pixel = result.projectedInFile;
        colour = QColor( 160, 160, 160 );
        icon = QgsVertexMarker::ICON_CIRCLE;
      }
      if ( !pixel )
        continue;
      QgsVertexMarker *marker = new QgsVertexMarker( view->canvas() );
      const Eigen::Vector2d at = pixel.value_or( Eigen::Vector2d::Zero() ); // (checked above)
      marker->setCenter( view->mapFromPixel( QPointF( at.x(), at.y() ) ) );
      marker->setIconType( icon );
      marker->setIconSize( 14 );
      marker->setPenWidth( 2 );
      marker->setColor( colour );
      marker->setToolTip( QString::fromStdString( points[i].pointId ) );
      mMarkers << qMakePair( QPointer<QgsMapCanvas>( view->canvas() ), marker );
    }
  }
}
