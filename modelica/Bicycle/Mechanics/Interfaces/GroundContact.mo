within Bicycle.Mechanics.Interfaces;
connector GroundContact "Rolling contact of a wheel with the ground, the ground's side (input): where the contact point is and how the wheel's material point there moves"
  constant Integer n = 6 "Number of generalized speeds of the system";
  input Bicycle.Units.Position rho[3] "Vector from the wheel centre to the contact point (ground axes)";
  input Bicycle.Units.Position p[3] "Position of the geometric contact point (ground axes)";
  input Bicycle.Units.Velocity v[3] "Velocity of the geometric contact point (it moves over the ground and around the tyre)";
  input Bicycle.Units.Length Bc[3, n] "Partial velocities of the material contact point relative to the wheel centre: w_wheel x rho = Bc*u";
  input Bicycle.Units.Acceleration bc0[3] "Acceleration remainder of the material contact point relative to the wheel centre";
  input Bicycle.Units.Length B[3, n] "Partial velocities of the material contact point: its velocity is B*u";
  input Bicycle.Units.Acceleration b0[3] "Acceleration remainder of the material contact point: its acceleration is B*du + b0";
  annotation(
    defaultComponentName = "contact",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {140, 70, 20}, fillColor = {140, 70, 20}, fillPattern = FillPattern.Backward),
      Line(points = {{-100, 100}, {100, 100}}, color = {140, 70, 20}, thickness = 0.5)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-40, -40}, {40, 40}}, lineColor = {140, 70, 20}, fillColor = {140, 70, 20}, fillPattern = FillPattern.Backward),
      Text(extent = {{-140, -50}, {140, -88}}, textString = "%name", textColor = {0, 0, 0})}),
    Documentation(info = "<html><p>The ground's side of
<a href=\"modelica://Bicycle.Mechanics.Interfaces.WheelContact\">WheelContact</a>: the same variables as
inputs.</p></html>"));
end GroundContact;
