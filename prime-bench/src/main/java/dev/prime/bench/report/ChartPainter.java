package dev.prime.bench.report;

import java.awt.BasicStroke;
import java.awt.Color;
import java.awt.Font;
import java.awt.FontMetrics;
import java.awt.Graphics2D;
import java.awt.RenderingHints;
import java.awt.geom.AffineTransform;
import java.awt.geom.Ellipse2D;
import java.awt.geom.Line2D;
import java.awt.geom.Path2D;
import java.awt.geom.Rectangle2D;
import java.awt.image.BufferedImage;
import java.io.IOException;
import java.math.BigDecimal;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.List;
import javax.imageio.ImageIO;

/**
 * Draws a {@link ChartModel} with Java2D into a PNG: the value axis on the left with its unit and
 * grid lines, a group per payload column along the bottom, a bar (linear axis) or a point (log
 * axis) per row in each group with its error bar, and the legend on the right, which names the
 * rows and says what the error bars are. Every geometric decision (scale, clipping) was made in
 * the model; this class only maps it to pixels. Needs no display ({@code java.awt.headless}).
 */
final class ChartPainter {
  /** The image's width in pixels. */
  static final int WIDTH = 1000;

  /** The image's height in pixels. */
  static final int HEIGHT = 560;

  private static final int LEFT = 90;
  private static final int TOP = 50;
  private static final int BOTTOM = 70;
  private static final int LEGEND_WIDTH = 300;
  private static final int POINT_RADIUS = 5;

  /** Okabe and Ito's palette, told apart with every colour vision; the baseline is dark grey. */
  private static final Color[] PALETTE = {
    new Color(0x0072B2), new Color(0xE69F00), new Color(0x009E73), new Color(0xCC79A7),
    new Color(0xD55E00), new Color(0x56B4E9), new Color(0x8C6D1F), new Color(0x7F3C8D)
  };
  private static final Color BASELINE = new Color(0x444444);
  private static final Color GRID = new Color(0xDDDDDD);
  private static final Color ERROR_BAR = Color.BLACK;

  private final ChartModel model;
  private final Graphics2D g;
  private final int plotLeft = LEFT;
  private final int plotRight = WIDTH - LEGEND_WIDTH;
  private final int plotTop = TOP;
  private final int plotBottom = HEIGHT - BOTTOM;

  private ChartPainter(ChartModel model, Graphics2D g) {
    this.model = model;
    this.g = g;
  }

  /**
   * Writes the chart as a PNG file of {@link #WIDTH} × {@link #HEIGHT} pixels.
   *
   * @param model the chart
   * @param file the file to write
   * @throws IOException if it cannot be written
   */
  static void writePng(ChartModel model, Path file) throws IOException {
    BufferedImage image = new BufferedImage(WIDTH, HEIGHT, BufferedImage.TYPE_INT_RGB);
    Graphics2D g = image.createGraphics();
    try {
      g.setRenderingHint(RenderingHints.KEY_ANTIALIASING, RenderingHints.VALUE_ANTIALIAS_ON);
      g.setRenderingHint(
          RenderingHints.KEY_TEXT_ANTIALIASING, RenderingHints.VALUE_TEXT_ANTIALIAS_ON);
      g.setColor(Color.WHITE);
      g.fillRect(0, 0, WIDTH, HEIGHT);
      new ChartPainter(model, g).paint();
    } finally {
      g.dispose();
    }
    if (!ImageIO.write(image, "png", file.toFile())) {
      throw new IOException("no PNG writer in this JDK: cannot write " + file);
    }
  }

  private void paint() {
    title();
    valueAxis();
    groups();
    marks();
    legend();
  }

  private void title() {
    g.setColor(Color.BLACK);
    g.setFont(new Font(Font.SANS_SERIF, Font.BOLD, 16));
    centred(model.title(), (plotLeft + plotRight) / 2.0, 28);
  }

  private void valueAxis() {
    g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 12));
    FontMetrics metrics = g.getFontMetrics();
    for (double tick : model.ticks()) {
      double y = y(tick);
      g.setColor(GRID);
      g.setStroke(new BasicStroke(1));
      g.draw(new Line2D.Double(plotLeft, y, plotRight, y));
      g.setColor(Color.BLACK);
      String label = BigDecimal.valueOf(tick).stripTrailingZeros().toPlainString();
      g.drawString(label, plotLeft - 8 - metrics.stringWidth(label),
          (float) (y + metrics.getAscent() / 2.0 - 1));
    }
    g.setColor(Color.BLACK);
    g.setStroke(new BasicStroke(1.5f));
    g.draw(new Line2D.Double(plotLeft, plotTop, plotLeft, plotBottom));
    g.draw(new Line2D.Double(plotLeft, plotBottom, plotRight, plotBottom));
    g.setFont(new Font(Font.SANS_SERIF, Font.BOLD, 13));
    AffineTransform saved = g.getTransform();
    g.rotate(-Math.PI / 2);
    centred(model.valueAxisTitle(), -(plotTop + plotBottom) / 2.0, 22);
    g.setTransform(saved);
  }

  private void groups() {
    g.setColor(Color.BLACK);
    g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 13));
    for (int i = 0; i < model.groups().size(); i++) {
      double left = groupLeft(i);
      centred(model.groups().get(i), left + groupWidth() / 2, plotBottom + 20);
      if (i > 0) {
        g.setColor(GRID);
        g.draw(new Line2D.Double(left, plotBottom, left, plotBottom + 8));
        g.setColor(Color.BLACK);
      }
    }
    g.setFont(new Font(Font.SANS_SERIF, Font.BOLD, 13));
    centred("payload per packet", (plotLeft + plotRight) / 2.0, plotBottom + 48);
  }

  private void marks() {
    int count = model.series().size();
    for (int s = 0; s < count; s++) {
      ChartModel.Series series = model.series().get(s);
      Color colour = colour(s);
      for (int i = 0; i < series.marks().size(); i++) {
        ChartModel.Mark mark = series.marks().get(i);
        if (mark == null) {
          continue;
        }
        double slot = groupWidth() * 0.8 / count;
        double x = groupLeft(i) + groupWidth() * 0.1 + slot * (s + 0.5);
        if (model.scale() == ChartModel.Scale.LINEAR) {
          double top = y(mark.value());
          g.setColor(colour);
          g.fill(new Rectangle2D.Double(x - slot * 0.4, top, slot * 0.8, plotBottom - top));
        }
        errorBar(mark, x, Math.min(slot * 0.5, 14));
        if (model.scale() == ChartModel.Scale.LOG) {
          point(colour, x, y(mark.value()));
        }
      }
    }
  }

  private void errorBar(ChartModel.Mark mark, double x, double capWidth) {
    if (!mark.hasError()) {
      return;
    }
    double top = y(mark.high());
    double bottom = y(mark.low());
    g.setColor(ERROR_BAR);
    g.setStroke(new BasicStroke(1.5f));
    g.draw(new Line2D.Double(x, top, x, bottom));
    g.draw(new Line2D.Double(x - capWidth / 2, top, x + capWidth / 2, top));
    if (mark.lowClipped()) {
      clippedArrow(x, bottom);
    } else {
      g.draw(new Line2D.Double(x - capWidth / 2, bottom, x + capWidth / 2, bottom));
    }
  }

  /** An arrow head pointing down at the axis: the interval goes on below it. */
  private void clippedArrow(double x, double bottom) {
    Path2D.Double arrow = new Path2D.Double();
    arrow.moveTo(x - 5, bottom - 9);
    arrow.lineTo(x + 5, bottom - 9);
    arrow.lineTo(x, bottom);
    arrow.closePath();
    g.setColor(ERROR_BAR);
    g.fill(arrow);
  }

  private void point(Color colour, double x, double y) {
    Ellipse2D.Double dot =
        new Ellipse2D.Double(x - POINT_RADIUS, y - POINT_RADIUS, 2 * POINT_RADIUS, 2 * POINT_RADIUS);
    g.setColor(colour);
    g.fill(dot);
    g.setColor(Color.BLACK);
    g.setStroke(new BasicStroke(1));
    g.draw(dot);
  }

  private void legend() {
    int x = plotRight + 24;
    int y = plotTop + 10;
    g.setFont(new Font(Font.SANS_SERIF, Font.PLAIN, 12));
    for (int s = 0; s < model.series().size(); s++) {
      Color colour = colour(s);
      if (model.scale() == ChartModel.Scale.LINEAR) {
        g.setColor(colour);
        g.fill(new Rectangle2D.Double(x, y - 10, 14, 14));
      } else {
        point(colour, x + 7, y - 3);
      }
      g.setColor(Color.BLACK);
      g.drawString(model.series().get(s).label(), x + 24, y + 2);
      y += 22;
    }
    y += 10;
    List<String> notes = new ArrayList<>();
    notes.add(model.scale() == ChartModel.Scale.LINEAR
        ? "bar: mean time, from zero"
        : "point: mean time (log axis, so no bars)");
    notes.add("error bar: 99.9 % confidence interval");
    notes.add("   of the mean (JMH score error)");
    if (model.anyClipped()) {
      notes.add(model.scale() == ChartModel.Scale.LINEAR
          ? "▼ interval reaches below zero"
          : "▼ interval reaches below the axis");
    }
    if (model.anyWithoutError()) {
      notes.add("no error bar: one iteration, unknown");
    }
    notes.add("lower is better");
    g.setColor(new Color(0x333333));
    for (String note : notes) {
      g.drawString(note, x, y);
      y += 18;
    }
  }

  private Color colour(int series) {
    if (model.series().get(series).baseline()) {
      return BASELINE;
    }
    return PALETTE[series % PALETTE.length];
  }

  private double y(double value) {
    return plotBottom - model.position(value) * (plotBottom - plotTop);
  }

  private double groupWidth() {
    return (plotRight - plotLeft) / (double) Math.max(1, model.groups().size());
  }

  private double groupLeft(int group) {
    return plotLeft + group * groupWidth();
  }

  private void centred(String text, double x, double baseline) {
    g.drawString(text, (float) (x - g.getFontMetrics().stringWidth(text) / 2.0), (float) baseline);
  }
}
