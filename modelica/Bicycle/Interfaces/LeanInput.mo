within Bicycle.Interfaces;
connector LeanInput "Lean of a body that moves relative to the rear frame, weighted with its inertia (input)"
  input Bicycle.Units.AngularMomentumIntegral H "J_r*theta: moment of inertia about the x axis times lean angle relative to the frame; der(H) is the body's angular momentum relative to the frame";
  annotation(
    defaultComponentName = "lean",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{-100, 100}, {100, 0}, {-100, -100}, {-100, 100}}, lineColor = {0, 0, 127}, fillColor = {0, 0, 127}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{0, 50}, {100, 0}, {0, -50}, {0, 50}}, lineColor = {0, 0, 127}, fillColor = {0, 0, 127}, fillPattern = FillPattern.Solid),
      Text(extent = {{-120, 60}, {80, 100}}, textString = "%name", textColor = {0, 0, 127})}));
end LeanInput;
