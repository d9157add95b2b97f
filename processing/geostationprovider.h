/***************************************************************************
  geostationprovider.h - the Processing provider "geostation"
 ***************************************************************************/
#ifndef GEOSTATIONPROVIDER_H
#define GEOSTATIONPROVIDER_H

#include <qgsprocessingprovider.h>

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

/**
 * Processing provider with id "geostation": every GeoStation capability as an
 * algorithm, so it runs from the toolbox, from models and headless through
 * qgis_process (docs/conventions.md §8).
 */
class GEOSTATION_PROCESSING_EXPORT GeoStationProvider : public QgsProcessingProvider
{
    Q_OBJECT

  public:
    explicit GeoStationProvider( QObject *parent = nullptr );

    QString id() const override;
    QString name() const override;
    QString longName() const override;
    QIcon icon() const override;
    QString svgIconPath() const override;
    bool supportsNonFileBasedOutput() const override;

  protected:
    void loadAlgorithms() override;
};

} // namespace GeoStationProcessing

/**
 * Adds the provider to QGIS's processing registry unless it is there already
 * (idempotent). Returns true when this call added it.
 */
GEOSTATION_PROCESSING_EXPORT bool registerGeoStationProvider();

//! Removes the provider from the registry if present; returns true if removed.
GEOSTATION_PROCESSING_EXPORT bool unregisterGeoStationProvider();

#endif // GEOSTATIONPROVIDER_H
