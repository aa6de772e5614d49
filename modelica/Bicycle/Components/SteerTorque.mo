within Bicycle.Components;
model SteerTorque "Torque applied by the rider to the handlebars"
  input Bicycle.Units.Torque T "Steer torque, positive counter-clockwise seen from above";
  Bicycle.Interfaces.Steer steer "Steer axis"
    annotation(Placement(transformation(extent = {{-10, -110}, {10, -90}})));
equation
  steer.tau = -T;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
      Line(points = {{0, 30}, {0, -100}}, color = {95, 95, 95}, thickness = 0.5),
      Rectangle(extent = {{-8, 40}, {8, 20}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
      Line(points = {{-70, 30}, {70, 30}}, color = {64, 64, 64}, thickness = 2),
      Rectangle(extent = {{-90, 38}, {-66, 22}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid, radius = 4),
      Rectangle(extent = {{66, 38}, {90, 22}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid, radius = 4),
      Line(points = {{-52.6, 10.8}, {-44.4, -4.1}, {-32.1, -15.9}, {-16.8, -23.4}, {0, -26}, {16.8, -23.4}, {32.1, -15.9}, {44.4, -4.1}, {52.6, 10.8}}, color = {255, 0, 0}, thickness = 0.75, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 8, smooth = Smooth.Bezier),
      Text(extent = {{-90, -20}, {90, -70}}, textString = "T", textColor = {0, 0, 0}),
      Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
end SteerTorque;
