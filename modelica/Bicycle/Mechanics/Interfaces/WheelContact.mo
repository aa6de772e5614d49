within Bicycle.Mechanics.Interfaces;
connector WheelContact "Rolling contact of a wheel with the ground, the wheel's side (output): where the contact point is and how the wheel's material point there moves"
  constant Integer n = 6 "Number of generalized speeds of the system";
  output Bicycle.Units.Position rho[3] "Vector from the wheel centre to the contact point (ground axes)";
  output Bicycle.Units.Position p[3] "Position of the geometric contact point (ground axes)";
  output Bicycle.Units.Velocity v[3] "Velocity of the geometric contact point (it moves over the ground and around the tyre)";
  output Bicycle.Units.Length Bc[3, n] "Partial velocities of the material contact point relative to the wheel centre: w_wheel x rho = Bc*u";
  output Bicycle.Units.Acceleration bc0[3] "Acceleration remainder of the material contact point relative to the wheel centre";
  output Bicycle.Units.Length B[3, n] "Partial velocities of the material contact point: its velocity is B*u";
  output Bicycle.Units.Acceleration b0[3] "Acceleration remainder of the material contact point: its acceleration is B*du + b0";
  annotation(
    defaultComponentName = "contact",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Polygon(points = {{-100, 100}, {-96.6, 48.2}, {-86.6, 0}, {-70.7, -41.4}, {-50, -73.2}, {-25.9, -93.2}, {0, -100}, {25.9, -93.2}, {50, -73.2}, {70.7, -41.4}, {86.6, 0}, {96.6, 48.2}, {100, 100}, {-100, 100}}, lineColor = {140, 70, 20}, fillColor = {140, 70, 20}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Polygon(points = {{-40, 40}, {-38.64, 19.28}, {-34.64, 0}, {-28.28, -16.56}, {-20, -29.28}, {-10.36, -37.28}, {0, -40}, {10.36, -37.28}, {20, -29.28}, {28.28, -16.56}, {34.64, 0}, {38.64, 19.28}, {40, 40}, {-40, 40}}, lineColor = {140, 70, 20}, fillColor = {140, 70, 20}, fillPattern = FillPattern.Solid),
      Text(extent = {{-140, -50}, {140, -88}}, textString = "%name", textColor = {0, 0, 0})}),
    Documentation(info = "<html><p>Rolling without slip means <code>B*u = 0</code> (three
nonholonomic constraints; the vertical one is the rate of the holonomic constraint
<code>p[3] = 0</code>) and, differentiated, <code>B*du + b0 = 0</code>. A wheel computes these rows
from its hub's kinematics; the ground
(<a href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a>, through a
<a href=\"modelica://Bicycle.Mechanics.Interfaces.GroundContact\">GroundContact</a>) imposes them.
The rows relative to the wheel centre (<code>Bc</code>, <code>bc0</code>) let the ground place the
wheel that carries the rear frame: its centre moves so that its contact point does not.</p>
<p>A signal connector (every variable causal): nothing is summed over a connection.</p></html>"));
end WheelContact;
