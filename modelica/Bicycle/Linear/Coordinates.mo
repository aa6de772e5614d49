within Bicycle.Linear;
model Coordinates "Roll and steer coordinates of the linearized bicycle: gives the components q and q', returns the accelerations q'' that the summed generalized forces determine"
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle phi (a state of the assembly)"
    annotation(Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Bicycle.Interfaces.RealInput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle delta (a state of the assembly)"
    annotation(Placement(transformation(extent = {{-140, 0}, {-100, 40}})));
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate der(phi) (a state of the assembly)"
    annotation(Placement(transformation(extent = {{-140, -40}, {-100, 0}})));
  Bicycle.Interfaces.RealInput delta_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Steer rate der(delta) (a state of the assembly)"
    annotation(Placement(transformation(extent = {{-140, -80}, {-100, -40}})));
  Bicycle.Interfaces.RealOutput phi_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Roll acceleration der(phi_dot)"
    annotation(Placement(transformation(extent = {{100, 30}, {120, 50}})));
  Bicycle.Interfaces.RealOutput delta_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Steer acceleration der(delta_dot)"
    annotation(Placement(transformation(extent = {{100, -50}, {120, -30}})));
  Bicycle.Linear.RollSteer_b frame "Roll and steer coordinates; the components' generalized forces meet here"
    annotation(Placement(transformation(extent = {{-16, 84}, {16, 116}})));
equation
  frame.phi = phi;
  frame.delta = delta;
  frame.phi_dot = phi_dot;
  frame.delta_dot = delta_dot;
  // No generalized force of its own: the flow sum of the connection set is Kane's equations
  // sum(Q) = 0 of the components, which determine the accelerations.
  frame.Q_phi = 0;
  frame.Q_delta = 0;
  phi_ddot = frame.phi_ddot;
  delta_ddot = frame.delta_ddot;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 128, 128}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid, lineThickness = 0.5),
      Text(extent = {{-90, 80}, {90, 40}}, textString = "q, q'", textColor = {0, 0, 0}),
      Line(points = {{0, 36}, {0, 4}}, color = {0, 0, 0}, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 8),
      Text(extent = {{-90, 0}, {90, -40}}, textString = "q''", textColor = {0, 0, 0}),
      Text(extent = {{-90, -50}, {90, -90}}, textString = "ΣQ = 0", textColor = {128, 128, 128}),
      Line(points = {{0, 84}, {0, 100}}, color = {0, 128, 128}, thickness = 0.5),
      Text(extent = {{-150, -110}, {150, -150}}, textString = "%name", textColor = {0, 0, 255})}),
    Documentation(info = "<html>
<p>The root of the connection set. It passes the coordinates q = [phi; delta] and speeds q'
(states of the assembly, so that they keep their names in an exported model) to the components
through the outputs of its <a href=\"modelica://Bicycle.Linear.RollSteer_b\">RollSteer_b</a>
connector, and gives the accelerations q'' of the connector as signals.</p>
<p>The coordinates carry no mass and no applied force: their generalized force is zero. Every
other component of the set delivers the generalized force that keeps it in d'Alembert equilibrium
(for a body Q_i = M_i q'' + v C1_i q' + (g K0_i + v^2 K2_i) q, for the torques
Q = -[T_phi; T_delta]), so the flow sum of the set is Kane's equations of the whole bicycle,</p>
<pre>  M q'' + v C1 q' + (g K0 + v^2 K2) q = [T_phi; T_delta],   M = sum of M_i, ...</pre>
<p>two equations linear in the two accelerations, which the connection shares as potentials.
Nobody writes M q'' = Q explicitly: the tool solves the connection set (with the mass matrix M
regular, a 2x2 linear system).</p>
</html>"));
end Coordinates;
