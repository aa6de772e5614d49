within Bicycle.Mechanics.Interfaces;
connector Frame_a "Frame on the side away from the ground: kinematics in (input), generalized speeds, accelerations, forces and energy as acausal pairs"
  constant Integer n = 6 "Number of generalized speeds of the system";
  input Bicycle.Units.DimensionlessRatio R[3, 3] "Orientation: the columns are the frame's x, y, z axes resolved in ground axes";
  input Bicycle.Units.Position r[3] "Position of the frame origin (ground axes; the ground is z = 0, z down)";
  input Bicycle.Units.AngularVelocity w[3] "Angular velocity of the frame (ground axes)";
  input Bicycle.Units.DimensionlessRatio Wp[3, n] "Partial angular velocities: w = Wp*u";
  input Bicycle.Units.AngularAcceleration al0[3] "Angular acceleration remainder: der(w) = Wp*du + al0";
  input Bicycle.Units.Length Vp[3, n] "Partial velocities of the origin: der(r) = Vp*u";
  input Bicycle.Units.Acceleration a0[3] "Acceleration remainder of the origin: der(der(r)) = Vp*du + a0";
  Bicycle.Units.AngularVelocity u[n] "Generalized speeds";
  flow Bicycle.Units.AngularVelocity us[n] "Generalized speeds owned by the joints beyond the frame (each joint adds its own speed in its own column)";
  Bicycle.Units.AngularAcceleration du[n] "Generalized accelerations der(u)";
  flow Bicycle.Units.Torque F[n] "Generalized forces of the bodies and joints beyond the frame, inertia included: Kane's sum of F_r + F_r*";
  Bicycle.Units.Acceleration g "Gravitational acceleration along the ground z axis (down), given by the ground";
  flow Bicycle.Units.Energy E "Mechanical energy of the bodies and springs beyond the frame: kinetic, gravitational (zero at the ground) and elastic";
  annotation(
    defaultComponentName = "frame_a",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-10, 10}, {10, -10}}, lineColor = {95, 95, 95}, lineThickness = 0.5),
      Rectangle(extent = {{-30, 100}, {30, -100}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Text(extent = {{-140, -50}, {140, -88}}, textString = "%name", textColor = {0, 0, 0}),
      Rectangle(extent = {{-12, 40}, {12, -40}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid)}),
    Documentation(info = "<html>
<p>The connector of the generalized-coordinate multibody components (Kane's method). It is
balanced (MLS 9.3.1) in the way the specification prescribes for such frames: the kinematics
travel causally from the ground outwards (<code>output</code> in
<a href=\"modelica://Bicycle.Mechanics.Interfaces.Frame_b\">Frame_b</a>, <code>input</code> here), and
three acausal pairs remain, each with as many flow as potential scalars:</p>
<ul>
<li><code>u</code> / <code>us</code>: the generalized speeds, the same in the whole system, and the
speeds that the joints own. A joint with coordinate <code>k</code> adds its speed to
<code>us[k]</code>; the ground reads every joint's speed from the sum and gives the vector
<code>u</code> (with the dependent speeds it solves from the rolling constraints).</li>
<li><code>du</code> / <code>F</code>: the generalized accelerations and the generalized forces. A body
adds <code>Vc'(F - m ac) + Wp'(T - I al - w x I w)</code>, with its accelerations
<code>ac = Vc*du + ac0</code>, <code>al = Wp*du + al0</code> written with <code>du</code>: the
connection sets sum Kane's generalized active and inertia forces, and the ground states Kane's
equations on the sum.</li>
<li><code>g</code> / <code>E</code>: the ground's gravity (as MultiBody's <code>world</code> gives it to
every body) and the mechanical energy of the bodies and springs beyond the frame.</li>
</ul>
<p>All vectors are resolved in ground axes (x forward at zero yaw, y right, z down). The
coordinate vector itself is not in the connector: each joint owns its coordinate (angle and speed)
and its column <code>k</code> of the partial velocities.</p>
</html>"));
end Frame_a;
