/***************************************************************************
  mergeroadnetworksalgorithm.h - geostation:merge_road_networks
  -------------------------------------------------------------------------
  The road networks that extract_roads made of overlapping pairs, made one
  (core/extraction/networkmerge.h): a road in an overlap once, roads
  across a pair's border joined, junctions kept; each line with the pairs
  that found it. What geostation-batch extract runs after its units.
 ***************************************************************************/
#ifndef MERGEROADNETWORKSALGORITHM_H
#define MERGEROADNETWORKSALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT MergeRoadNetworksAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    MergeRoadNetworksAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // MERGEROADNETWORKSALGORITHM_H
