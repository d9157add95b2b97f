/***************************************************************************
  geostationprovider.cpp - the Processing provider "geostation"
 ***************************************************************************/
#include "geostationprovider.h"

#include <QFile>
#include <QIcon>

#include <qgsapplication.h>
#include <qgsprocessingregistry.h>

#include "bundleadjustalgorithm.h"
#include "enhanceimagealgorithm.h"
#include "exportmeasurementsalgorithm.h"
#include "innerorientationalgorithm.h"
#include "intersectalgorithm.h"
#include "matchpointsalgorithm.h"
#include "monoplotalgorithm.h"
#include "simulatesurveyalgorithm.h"
#include "traceroadlinesalgorithm.h"
#include "extractroadsalgorithm.h"
#include "reviseroadsalgorithm.h"
#include "mergeroadnetworksalgorithm.h"
#include "mergerevisionsalgorithm.h"
#include "jointracedpiecesalgorithm.h"
#include "exportblockalgorithm.h"
#include "identifycontrolalgorithm.h"
#include "importblockalgorithm.h"
#include "projecttoimagealgorithm.h"
#include "resectionalgorithm.h"

namespace GeoStationProcessing
{

namespace
{
  const char *kProviderId = "geostation";
}

GeoStationProvider::GeoStationProvider( QObject *parent )
  : QgsProcessingProvider( parent )
{}

QString GeoStationProvider::id() const
{
  return QString::fromLatin1( kProviderId );
}

QString GeoStationProvider::name() const
{
  return QStringLiteral( "GeoStation" );
}

QString GeoStationProvider::longName() const
{
  return QStringLiteral( "GeoStation softcopy photogrammetry" );
}

QString GeoStationProvider::svgIconPath() const
{
  return QStringLiteral( ":/geostation/icons/geostation.svg" );
}

QIcon GeoStationProvider::icon() const
{
  return QFile::exists( svgIconPath() ) ? QIcon( svgIconPath() ) : QgsProcessingProvider::icon();
}

bool GeoStationProvider::supportsNonFileBasedOutput() const
{
  return true;
}

void GeoStationProvider::loadAlgorithms()
{
  addAlgorithm( new ProjectToImageAlgorithm() );
  addAlgorithm( new IntersectAlgorithm() );
  addAlgorithm( new ResectionAlgorithm() );
  addAlgorithm( new BundleAdjustAlgorithm() );
  addAlgorithm( new InnerOrientationAlgorithm() );
  addAlgorithm( new MonoplotAlgorithm() );
  addAlgorithm( new SimulateSurveyAlgorithm() );
  addAlgorithm( new EnhanceImageAlgorithm() );
  addAlgorithm( new MatchPointsAlgorithm() );
  addAlgorithm( new ExportMeasurementsAlgorithm() );
  addAlgorithm( new TraceRoadLinesAlgorithm() );
  addAlgorithm( new ExtractRoadsAlgorithm() );
  addAlgorithm( new ReviseRoadsAlgorithm() );
  addAlgorithm( new MergeRoadNetworksAlgorithm() );
  addAlgorithm( new MergeRevisionsAlgorithm() );
  addAlgorithm( new JoinTracedPiecesAlgorithm() );
  addAlgorithm( new ImportBlockAlgorithm() );
  addAlgorithm( new ExportBlockAlgorithm() );
  addAlgorithm( new IdentifyControlAlgorithm() );
}

} // namespace GeoStationProcessing

bool registerGeoStationProvider()
{
  QgsProcessingRegistry *registry = QgsApplication::processingRegistry();
  if ( !registry || registry->providerById( QString::fromLatin1( GeoStationProcessing::kProviderId ) ) )
    return false;
  return registry->addProvider( new GeoStationProcessing::GeoStationProvider( registry ) );
}

bool unregisterGeoStationProvider()
{
  QgsProcessingRegistry *registry = QgsApplication::processingRegistry();
  if ( !registry )
    return false;
  QgsProcessingProvider *provider = registry->providerById( QString::fromLatin1( GeoStationProcessing::kProviderId ) );
  return provider && registry->removeProvider( provider );
}

// The entry points that the Python bridge calls through ctypes, so that
// qgis_process (which loads only Python plugins) sees the provider.
extern "C" GEOSTATION_PROCESSING_EXPORT int geostation_register_provider()
{
  return registerGeoStationProvider() ? 1 : 0;
}

extern "C" GEOSTATION_PROCESSING_EXPORT int geostation_unregister_provider()
{
  return unregisterGeoStationProvider() ? 1 : 0;
}
