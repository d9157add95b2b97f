/***************************************************************************
  geostationalgorithm.cpp
 ***************************************************************************/
#include "geostationalgorithm.h"
#include "userguide.h"

#include <new>
#include <stdexcept>

#include <QRegularExpression>

#include <qgsprocessingfeedback.h>
#include <qgsprocessingoutputs.h>
#include <qgsprocessingparameters.h>
#include <qgsprocessingutils.h>

namespace GeoStationProcessing
{

QVariantMap GeoStationAlgorithm::processAlgorithm( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback )
{
  try
  {
    return processGeoStation( withChoicesByName( parameters ), context, feedback );
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

QString GeoStationAlgorithm::shortHelpString() const
{
  QList<QPair<QString, QString>> named; // name, label
  for ( const QgsProcessingParameterDefinition *p : parameterDefinitions() )
    named << qMakePair( p->name(), p->description() );
  for ( const QgsProcessingOutputDefinition *o : outputDefinitions() )
    if ( !parameterDefinition( o->name() ) )
      named << qMakePair( o->name(), o->description() );
  QString text = helpText();
  for ( const auto &[name, description] : named )
  {
    const int bracket = description.indexOf( QLatin1String( " (" ) );
    const QString label = bracket > 0 ? description.left( bracket ) : description;
    if ( label.isEmpty() || label.compare( name, Qt::CaseInsensitive ) == 0 )
      continue; // "DEM" (DEM) says nothing more
    text.replace( QRegularExpression( QStringLiteral( "\\b%1\\b" ).arg( QRegularExpression::escape( name ) ) ), QStringLiteral( "\u201c%1\u201d (%2)" ).arg( label, name ) );
  }
  return text;
}

QString GeoStationAlgorithm::helpUrl() const
{
  return userGuidePage( QStringLiteral( "algorithms/%1.html" ).arg( name() ) );
}

bool GeoStationAlgorithm::checkParameterValues( const QVariantMap &parameters, QgsProcessingContext &context, QString *message ) const
{
  return QgsProcessingAlgorithm::checkParameterValues( withChoicesByName( parameters ), context, message );
}

namespace
{
  //! The option an index names (an int, or text that is a whole number within range); the value itself otherwise.
  QVariant optionOfIndex( const QVariant &value, const QStringList &options )
  {
    if ( value.type() == QVariant::String && options.contains( value.toString() ) )
      return value;
    bool isIndex = false;
    const int index = value.toString().trimmed().toInt( &isIndex );
    return isIndex && index >= 0 && index < options.size() ? QVariant( options.at( index ) ) : value;
  }
}

QVariantMap GeoStationAlgorithm::withChoicesByName( const QVariantMap &parameters ) const
{
  QVariantMap out = parameters;
  for ( const QgsProcessingParameterDefinition *definition : parameterDefinitions() )
  {
    const QgsProcessingParameterEnum *choice = dynamic_cast<const QgsProcessingParameterEnum *>( definition );
    if ( !choice || !choice->usesStaticStrings() || !out.contains( choice->name() ) )
      continue;
    QVariant &value = out[choice->name()];
    if ( value.type() == QVariant::List || value.type() == QVariant::StringList )
    {
      QVariantList names;
      for ( const QVariant &v : value.toList() )
        names << optionOfIndex( v, choice->options() );
      value = names;
    }
    else if ( choice->allowMultiple() && value.type() == QVariant::String && value.toString().contains( ',' ) )
    {
      QVariantList names;
      for ( const QString &part : value.toString().split( ',' ) )
        names << optionOfIndex( part.trimmed(), choice->options() );
      value = names;
    }
    else if ( value.isValid() && !value.isNull() )
      value = optionOfIndex( value, choice->options() );
  }
  return out;
}

bool GeoStationAlgorithm::outputRequested( const QVariantMap &parameters, const QString &name )
{
  const QVariant value = parameters.value( name );
  if ( !value.isValid() || value.isNull() )
    return false;
  if ( value.userType() == qMetaTypeId<QgsProcessingOutputLayerDefinition>() )
  {
    const QgsProcessingOutputLayerDefinition definition = value.value<QgsProcessingOutputLayerDefinition>();
    return definition.sink.propertyType() != QgsProperty::StaticProperty || !definition.sink.staticValue().toString().trimmed().isEmpty();
  }
  return !value.toString().trimmed().isEmpty();
}

OutputSink GeoStationAlgorithm::openOutput( const QVariantMap &parameters, const QString &name, QgsProcessingContext &context, const QgsFields &fields,
                                            QgsWkbTypes::Type type, const QgsCoordinateReferenceSystem &crs ) const
{
  QString destination;
  QgsFeatureSink *sink = parameterAsSink( parameters, name, context, destination, fields, type, crs );
  return OutputSink( sink, destination, parameters, name );
}

} // namespace GeoStationProcessing
