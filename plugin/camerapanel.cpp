/***************************************************************************
  camerapanel.cpp
 ***************************************************************************/
#include "camerapanel.h"

#include "io/block.h"

GeoStationCameraPanel::GeoStationCameraPanel( QWidget *parent )
  : QTableWidget( parent )
{
  setObjectName( QStringLiteral( "mCameraTable" ) );
  setEditTriggers( QAbstractItemView::NoEditTriggers );
}

void GeoStationCameraPanel::showImages( const geostation::Block *block, const QStringList &ids )
{
  const QStringList headers { tr( "Image" ), tr( "Camera" ), tr( "f [px]" ), tr( "cx" ), tr( "cy" ), tr( "Lens" ), tr( "X [m]" ), tr( "Y [m]" ), tr( "Z [m]" ),
                              tr( "ω [°]" ), tr( "φ [°]" ), tr( "κ [°]" ), tr( "σ X/Y/Z [m]" ), tr( "σ ω/φ/κ [°]" ) };
  clear();
  setColumnCount( headers.size() );
  setHorizontalHeaderLabels( headers );
  setRowCount( 0 );
  if ( !block )
    return;
  for ( const QString &id : ids )
  {
    const geostation::BlockImage *image = id.isEmpty() ? nullptr : block->findImage( id.toStdString() );
    if ( !image )
      continue;
    const geostation::Camera &camera = block->cameraOf( *image );
    QStringList cells { id, QString::fromStdString( camera.id ), QString::number( camera.f, 'f', 2 ), QString::number( camera.cx, 'f', 2 ), QString::number( camera.cy, 'f', 2 ),
                        QString::fromStdString( geostation::distortionModelName( camera.distortion.model ) ) };
    if ( image->exterior )
    {
      const geostation::ExteriorOrientation &eo = *image->exterior;
      cells << QString::number( eo.projectionCentre.x(), 'f', 3 ) << QString::number( eo.projectionCentre.y(), 'f', 3 ) << QString::number( eo.projectionCentre.z(), 'f', 3 )
            << QString::number( eo.omegaDeg, 'f', 4 ) << QString::number( eo.phiDeg, 'f', 4 ) << QString::number( eo.kappaDeg, 'f', 4 );
      if ( eo.sigma )
        cells << QStringLiteral( "%1 / %2 / %3" ).arg( eo.sigma->x, 0, 'f', 3 ).arg( eo.sigma->y, 0, 'f', 3 ).arg( eo.sigma->z, 0, 'f', 3 )
              << QStringLiteral( "%1 / %2 / %3" ).arg( eo.sigma->omegaDeg, 0, 'f', 3 ).arg( eo.sigma->phiDeg, 0, 'f', 3 ).arg( eo.sigma->kappaDeg, 0, 'f', 3 );
    }
    else
      cells << tr( "not oriented" );
    const int row = rowCount();
    insertRow( row );
    for ( int c = 0; c < cells.size(); ++c )
      setItem( row, c, new QTableWidgetItem( cells[c] ) );
  }
  resizeColumnsToContents();
}
