/***************************************************************************
  geostationalgorithm.cpp
 ***************************************************************************/
#include "geostationalgorithm.h"

#include <new>
#include <stdexcept>

#include <qgsprocessingfeedback.h>

namespace GeoStationProcessing
{

QVariantMap GeoStationAlgorithm::processAlgorithm( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  try
  {
    return processGeoStation( parameters, context, feedback );
  }
  catch ( const QgsProcessingException & )
  {
    throw;
  }
  catch ( const std::bad_alloc & )
  {
    throw QgsProcessingException( QObject::tr( "%1 ran out of memory; nothing was written. Try a smaller input (fewer features, a smaller image or DEM)." ).arg( displayName() ) );
  }
  catch ( const std::exception &e )
  {
    throw QgsProcessingException( QObject::tr( "%1 stopped: %2" ).arg( displayName(), QString::fromStdString( e.what() ) ) );
  }
}

} // namespace GeoStationProcessing
