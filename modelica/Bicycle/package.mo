within;
package Bicycle "Bicycle dynamics and control after Astrom, Klein and Lennartsson (IEEE CSM 2005)"
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {200, 200, 200}, fillColor = {248, 248, 248}, fillPattern = FillPattern.HorizontalCylinder, radius = 25),
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {128, 128, 128}, radius = 25),
      Ellipse(extent = {{-73.6, -51.2}, {-16, 6.4}}, lineColor = {0, 0, 0}, lineThickness = 0.75),
      Ellipse(extent = {{-68.8, -46.4}, {-20.8, 1.6}}, lineColor = {160, 160, 160}),
      Ellipse(extent = {{-48, -25.6}, {-41.6, -19.2}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{16, -51.2}, {73.6, 6.4}}, lineColor = {0, 0, 0}, lineThickness = 0.75),
      Ellipse(extent = {{20.8, -46.4}, {68.8, 1.6}}, lineColor = {160, 160, 160}),
      Ellipse(extent = {{41.6, -25.6}, {48, -19.2}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
      Line(points = {{-44.8, -22.4}, {-9.6, -27.2}, {-19.2, 22.4}, {-44.8, -22.4}}, color = {64, 64, 64}, thickness = 0.75),
      Line(points = {{-19.2, 22.4}, {25.6, 22.4}, {30.4, 9.6}, {-9.6, -27.2}}, color = {64, 64, 64}, thickness = 0.75),
      Line(points = {{-19.2, 22.4}, {-21.6, 30.4}}, color = {64, 64, 64}, thickness = 0.75),
      Line(points = {{-30.4, 31.2}, {-12.8, 31.2}}, color = {0, 0, 0}, thickness = 1.5),
      Line(points = {{30.4, 9.6}, {41.6, -16}, {44.8, -22.4}}, color = {64, 64, 64}, thickness = 0.75, smooth = Smooth.Bezier),
      Line(points = {{25.6, 22.4}, {24, 28.8}, {15.2, 31.2}, {12.8, 27.2}}, color = {64, 64, 64}, thickness = 0.75),
      Ellipse(extent = {{-14.4, -32}, {-4.8, -22.4}}, lineColor = {64, 64, 64})}),
    version = "0.1.0",
    Documentation(info = "<html>
<p>Component models of a bicycle (rear frame with rider, front fork, wheels, leaning rider)
assembled into the models of K. J. Astrom, R. E. Klein and A. Lennartsson, <em>Bicycle Dynamics
and Control</em>, IEEE Control Systems Magazine 25(4), 2005. Equation numbers in the descriptions
refer to that paper.</p>
<p>Sign conventions: the second-order models follow the paper (ISO 8855: x forward, y left, z up;
steer angle positive to the left), the Whipple family follows Meijaard et al. (2007) (x forward,
y right, z down; steer angle positive to the right); roll angles agree. See
<a href=\"modelica://Bicycle.UsersGuide.Conventions\">UsersGuide.Conventions</a>.</p>
<p>Models marked with the vendor annotation <code>__Cosim(export = true)</code> are exported as
FMUs by <code>cosim build</code>.</p>
</html>"));
end Bicycle;
