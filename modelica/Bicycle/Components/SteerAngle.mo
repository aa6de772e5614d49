within Bicycle.Components;
model SteerAngle "Steer angle imposed by the rider on a vertical steer axis (lambda = 90 deg): the control variable of model (1)"
  input Bicycle.Units.Angle delta "Steer angle, positive steering to the left";
  Bicycle.Interfaces.EffectiveSteerOutput front "Effective steer angle (equal to the steer angle for a vertical steer axis)"
    annotation(Placement(transformation(origin = {-110, 40}, extent = {{-10, -10}, {10, 10}}, rotation = 180)));
equation
  front.delta_f = delta;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
      Line(points = {{-80, -20}, {80, -20}}, color = {128, 128, 128}, pattern = LinePattern.Dash),
      Line(points = {{-76, -48}, {76, 8}}, color = {64, 64, 64}, thickness = 2),
      Rectangle(extent = {{-8, -10}, {8, -30}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
      Line(points = {{60, -20}, {59.8, -14.8}, {59.1, -9.6}, {58, -4.5}, {56.4, 0.5}}, color = {255, 0, 0}, thickness = 0.5, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 6, smooth = Smooth.Bezier),
      Text(extent = {{10, 80}, {90, 30}}, textString = "δ", textColor = {0, 0, 0}),
      Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
end SteerAngle;
