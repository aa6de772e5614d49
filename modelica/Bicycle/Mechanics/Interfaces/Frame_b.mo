within Bicycle.Mechanics.Interfaces;
connector Frame_b "Frame on the side of the ground: kinematics out (output), generalized speeds, accelerations, forces and energy as acausal pairs"
  constant Integer n = 6 "Number of generalized speeds of the system";
  output Bicycle.Units.DimensionlessRatio R[3, 3] "Orientation: the columns are the frame's x, y, z axes resolved in ground axes";
  output Bicycle.Units.Position r[3] "Position of the frame origin (ground axes; the ground is z = 0, z down)";
  output Bicycle.Units.AngularVelocity w[3] "Angular velocity of the frame (ground axes)";
  output Bicycle.Units.DimensionlessRatio Wp[3, n] "Partial angular velocities: w = Wp*u";
  output Bicycle.Units.AngularAcceleration al0[3] "Angular acceleration remainder: der(w) = Wp*du + al0";
  output Bicycle.Units.Length Vp[3, n] "Partial velocities of the origin: der(r) = Vp*u";
  output Bicycle.Units.Acceleration a0[3] "Acceleration remainder of the origin: der(der(r)) = Vp*du + a0";
  Bicycle.Units.AngularVelocity u[n] "Generalized speeds";
  flow Bicycle.Units.AngularVelocity us[n] "Generalized speeds owned by the joints beyond the frame (each joint adds its own speed in its own column)";
  Bicycle.Units.AngularAcceleration du[n] "Generalized accelerations der(u)";
  flow Bicycle.Units.Torque F[n] "Generalized forces of the bodies and joints beyond the frame, inertia included: Kane's sum of F_r + F_r*";
  Bicycle.Units.Acceleration g "Gravitational acceleration along the ground z axis (down), given by the ground";
  flow Bicycle.Units.Energy E "Mechanical energy of the bodies and springs beyond the frame: kinetic, gravitational (zero at the ground) and elastic";
  annotation(
    defaultComponentName = "frame_b",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-10, 10}, {10, -10}}, lineColor = {95, 95, 95}, lineThickness = 0.5),
      Rectangle(extent = {{-30, 100}, {30, -100}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Text(extent = {{-140, -50}, {140, -88}}, textString = "%name", textColor = {0, 0, 0}),
      Rectangle(extent = {{-12, 40}, {12, -40}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid)}),
    Documentation(info = "<html>
<p>The same variables as <a href=\"modelica://Bicycle.Mechanics.Interfaces.Frame_a\">Frame_a</a>, on the side that
computes the kinematics: the ground, and the outer frame of a joint or a fixed translation.
Connect a <code>Frame_b</code> to any number of <code>Frame_a</code> (one source of the kinematics in
each connection set).</p>
</html>"));
end Frame_b;
