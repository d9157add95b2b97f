/***************************************************************************
  htmlreport.cpp - the report a person reads, as one HTML file
 ***************************************************************************/
#include "htmlreport.h"

#include <algorithm>
#include <cmath>

namespace GeoStationProcessing
{
  namespace
  {
    constexpr double kPlotWidth = 560.0;
    constexpr double kMargin = 12.0;

    QString escaped( const QString &text )
    {
      return text.toHtmlEscaped();
    }

    QString svgNumber( double v )
    {
      return QString::number( v, 'f', 1 );
    }

    //! An SVG of kPlotWidth and `height` opened, with `frame` drawn scaled by `toSvg` inside the margin.
    QString framedSvg( const QSizeF &frame, double toSvg, double height )
    {
      return QStringLiteral( "<figure><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%1\" height=\"%2\" viewBox=\"0 0 %1 %2\">\n" )
               .arg( svgNumber( kPlotWidth ), svgNumber( height ) ) +
             QStringLiteral( "<rect x=\"%1\" y=\"%1\" width=\"%2\" height=\"%3\" fill=\"#f6f6f6\" stroke=\"#888\"/>\n" )
               .arg( svgNumber( kMargin ), svgNumber( frame.width() * toSvg ), svgNumber( frame.height() * toSvg ) );
    }
  } // namespace

  QString number( double value, int decimals )
  {
    if ( !std::isfinite( value ) )
      return QStringLiteral( "-" );
    const QString text = QString::number( value, 'f', decimals );
    // -0.000: a value that rounds to zero is shown without a sign
    return text.startsWith( '-' ) && text.toDouble() == 0.0 ? text.mid( 1 ) : text;
  }

  double roundDown125( double value )
  {
    const double power = std::pow( 10.0, std::floor( std::log10( value ) ) );
    for ( const double step : { 5.0, 2.0, 1.0 } )
      if ( step * power <= value * ( 1.0 + 1e-9 ) )
        return step * power;
    return power;
  }

  HtmlReport::HtmlReport( const QString &title )
    : mTitle( title )
  {
  }

  void HtmlReport::heading( const QString &text )
  {
    mBody += QStringLiteral( "<h2>%1</h2>\n" ).arg( escaped( text ) );
  }

  void HtmlReport::paragraph( const QString &text )
  {
    mBody += QStringLiteral( "<p>%1</p>\n" ).arg( escaped( text ) );
  }

  void HtmlReport::keyValues( const QVector<QPair<QString, QString>> &rows )
  {
    mBody += QStringLiteral( "<table class=\"summary\">\n" );
    for ( const QPair<QString, QString> &row : rows )
      mBody += QStringLiteral( "<tr><th>%1</th><td>%2</td></tr>\n" ).arg( escaped( row.first ), escaped( row.second ) );
    mBody += QStringLiteral( "</table>\n" );
  }

  void HtmlReport::table( const QStringList &headers, const QVector<QStringList> &rows )
  {
    mBody += QStringLiteral( "<table>\n<tr>" );
    for ( const QString &h : headers )
      mBody += QStringLiteral( "<th>%1</th>" ).arg( escaped( h ) );
    mBody += QStringLiteral( "</tr>\n" );
    for ( const QStringList &row : rows )
    {
      mBody += QStringLiteral( "<tr>" );
      for ( const QString &cell : row )
        mBody += QStringLiteral( "<td>%1</td>" ).arg( escaped( cell ) );
      mBody += QStringLiteral( "</tr>\n" );
    }
    mBody += QStringLiteral( "</table>\n" );
  }

  void HtmlReport::residualPlot( const QString &caption, const QSizeF &frame, const QVector<ResidualArrow> &arrows, const QString &unit )
  {
    if ( !( frame.width() > 0.0 ) || !( frame.height() > 0.0 ) )
      return;
    double longest = 0.0;
    for ( const ResidualArrow &a : arrows )
      if ( std::isfinite( a.residual.x() ) && std::isfinite( a.residual.y() ) )
        longest = std::max( longest, std::hypot( a.residual.x(), a.residual.y() ) );
    // the longest arrow about a tenth of the frame's longer side
    const double magnify = longest > 0.0 ? roundDown125( 0.1 * std::max( frame.width(), frame.height() ) / longest ) : 1.0;
    const double toSvg = ( kPlotWidth - 2.0 * kMargin ) / frame.width();
    const double height = frame.height() * toSvg + 2.0 * kMargin + 28.0;
    ++mPlots;
    const QString arrowId = QStringLiteral( "arrow%1" ).arg( mPlots ), flaggedId = QStringLiteral( "flagged%1" ).arg( mPlots );
    QString svg = framedSvg( frame, toSvg, height );
    svg += QStringLiteral( "<defs><marker id=\"%1\" markerWidth=\"8\" markerHeight=\"8\" refX=\"7\" refY=\"4\" orient=\"auto\"><path d=\"M0,0 L8,4 L0,8 z\" fill=\"#1f5fa8\"/></marker>"
                           "<marker id=\"%2\" markerWidth=\"8\" markerHeight=\"8\" refX=\"7\" refY=\"4\" orient=\"auto\"><path d=\"M0,0 L8,4 L0,8 z\" fill=\"#c0392b\"/></marker></defs>\n" )
             .arg( arrowId, flaggedId );
    for ( const ResidualArrow &a : arrows )
    {
      const double x0 = kMargin + a.at.x() * toSvg, y0 = kMargin + a.at.y() * toSvg;
      if ( !std::isfinite( x0 ) || !std::isfinite( y0 ) )
        continue;
      const QString colour = a.flagged ? QStringLiteral( "#c0392b" ) : QStringLiteral( "#1f5fa8" );
      svg += QStringLiteral( "<g><title>%1</title><circle cx=\"%2\" cy=\"%3\" r=\"2\" fill=\"%4\"/>" ).arg( escaped( a.label ), svgNumber( x0 ), svgNumber( y0 ), colour );
      // an arrow shorter than its head is left out: the point alone says "no residual to see"
      if ( std::isfinite( a.residual.x() ) && std::isfinite( a.residual.y() ) && std::hypot( a.residual.x(), a.residual.y() ) * magnify * toSvg >= 3.0 )
        svg += QStringLiteral( "<line x1=\"%1\" y1=\"%2\" x2=\"%3\" y2=\"%4\" stroke=\"%5\" stroke-width=\"1.5\" marker-end=\"url(#%6)\"/>" )
                 .arg( svgNumber( x0 ), svgNumber( y0 ), svgNumber( x0 + a.residual.x() * magnify * toSvg ), svgNumber( y0 + a.residual.y() * magnify * toSvg ), colour,
                       a.flagged ? flaggedId : arrowId );
      svg += QStringLiteral( "</g>\n" );
    }
    // a scale bar: a round residual as drawn
    const double barResidual = longest > 0.0 ? roundDown125( longest ) : 1.0;
    const double barY = height - 14.0, barLength = barResidual * magnify * toSvg;
    svg += QStringLiteral( "<line x1=\"%1\" y1=\"%2\" x2=\"%3\" y2=\"%2\" stroke=\"#000\" stroke-width=\"2\"/>" ).arg( svgNumber( kMargin ), svgNumber( barY ), svgNumber( kMargin + barLength ) );
    svg += QStringLiteral( "<text x=\"%1\" y=\"%2\" font-size=\"12\">%3 %4 (residuals drawn %5 times their size)</text>\n" )
             .arg( svgNumber( kMargin + barLength + 8.0 ), svgNumber( barY + 4.0 ), escaped( QString::number( barResidual ) ), escaped( unit ), QString::number( magnify ) );
    svg += QStringLiteral( "</svg><figcaption>%1</figcaption></figure>\n" ).arg( escaped( caption ) );
    mBody += svg;
  }

  void HtmlReport::linesPlot( const QString &caption, const QSizeF &frame, const QVector<QPolygonF> &lines )
  {
    if ( !( frame.width() > 0.0 ) || !( frame.height() > 0.0 ) )
      return;
    const double toSvg = ( kPlotWidth - 2.0 * kMargin ) / frame.width();
    QString svg = framedSvg( frame, toSvg, frame.height() * toSvg + 2.0 * kMargin );
    for ( const QPolygonF &line : lines )
    {
      QStringList points;
      for ( const QPointF &p : line )
        if ( std::isfinite( p.x() ) && std::isfinite( p.y() ) )
          points << svgNumber( kMargin + p.x() * toSvg ) + ',' + svgNumber( kMargin + p.y() * toSvg );
      if ( points.size() >= 2 )
        svg += QStringLiteral( "<polyline points=\"%1\" fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"1.5\"/>\n" ).arg( points.join( ' ' ) );
    }
    svg += QStringLiteral( "</svg><figcaption>%1</figcaption></figure>\n" ).arg( escaped( caption ) );
    mBody += svg;
  }

  void HtmlReport::histogram( const QString &caption, const QVector<double> &values, const QString &unit )
  {
    QVector<double> finite;
    for ( const double v : values )
      if ( std::isfinite( v ) )
        finite << v;
    if ( finite.isEmpty() )
      return;
    double low = *std::min_element( finite.begin(), finite.end() ), high = *std::max_element( finite.begin(), finite.end() );
    if ( !( high > low ) )
    {
      low -= 0.5;
      high += 0.5;
    }
    const int bins = std::clamp( static_cast<int>( std::lround( std::sqrt( finite.size() ) ) ), 5, 30 );
    const double binWidth = ( high - low ) / bins;
    QVector<int> counts( bins, 0 );
    for ( const double v : finite )
      ++counts[std::min( bins - 1, static_cast<int>( ( v - low ) / binWidth ) )];
    const int most = *std::max_element( counts.begin(), counts.end() );
    // enough decimals to tell a bin's ends apart
    const int decimals = std::clamp( 2 - static_cast<int>( std::floor( std::log10( binWidth ) ) ), 0, 9 );
    constexpr double kBarsHeight = 160.0;
    const double barWidth = ( kPlotWidth - 2.0 * kMargin ) / bins;
    QString svg = QStringLiteral( "<figure><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%1\" height=\"%2\" viewBox=\"0 0 %1 %2\">\n" )
                    .arg( svgNumber( kPlotWidth ), svgNumber( kBarsHeight + 2.0 * kMargin + 24.0 ) );
    for ( int b = 0; b < bins; ++b )
    {
      const double h = kBarsHeight * counts[b] / most;
      svg += QStringLiteral( "<rect x=\"%1\" y=\"%2\" width=\"%3\" height=\"%4\" fill=\"#1f5fa8\" stroke=\"#fff\"><title>%5 to %6 %7: %8</title></rect>\n" )
               .arg( svgNumber( kMargin + b * barWidth ), svgNumber( kMargin + kBarsHeight - h ), svgNumber( barWidth ), svgNumber( h ),
                     number( low + b * binWidth, decimals ), number( low + ( b + 1 ) * binWidth, decimals ), escaped( unit ) )
               .arg( counts[b] );
    }
    const double axisY = kMargin + kBarsHeight;
    svg += QStringLiteral( "<line x1=\"%1\" y1=\"%2\" x2=\"%3\" y2=\"%2\" stroke=\"#000\"/>\n" ).arg( svgNumber( kMargin ), svgNumber( axisY ), svgNumber( kPlotWidth - kMargin ) );
    svg += QStringLiteral( "<text x=\"%1\" y=\"%2\" font-size=\"12\">%3</text><text x=\"%4\" y=\"%2\" font-size=\"12\" text-anchor=\"end\">%5 %6</text>\n" )
             .arg( svgNumber( kMargin ), svgNumber( axisY + 16.0 ), number( low, decimals ), svgNumber( kPlotWidth - kMargin ), number( high, decimals ), escaped( unit ) );
    svg += QStringLiteral( "<text x=\"%1\" y=\"%2\" font-size=\"12\">highest bar: %3 of %4</text>\n" ).arg( svgNumber( kMargin + 4.0 ), svgNumber( kMargin + 12.0 ) ).arg( most ).arg( finite.size() );
    svg += QStringLiteral( "</svg><figcaption>%1</figcaption></figure>\n" ).arg( escaped( caption ) );
    mBody += svg;
  }

  QByteArray HtmlReport::toUtf8() const
  {
    const QString page = QStringLiteral( "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"/><title>%1</title>\n"
                                         "<style>body{font-family:sans-serif;margin:2em;max-width:60em}table{border-collapse:collapse;margin:0.5em 0 1.5em}"
                                         "th,td{border:1px solid #ccc;padding:0.2em 0.6em;text-align:right;white-space:nowrap}th{background:#eee}"
                                         "table.summary th{text-align:left}figure{margin:1em 0}figcaption{font-size:90%;color:#444}</style>\n"
                                         "</head><body>\n<h1>%1</h1>\n%2</body></html>\n" )
                           .arg( escaped( mTitle ), mBody );
    return page.toUtf8();
  }

} // namespace GeoStationProcessing
