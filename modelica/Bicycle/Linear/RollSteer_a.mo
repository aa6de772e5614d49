within Bicycle.Linear;
connector RollSteer_a "Roll and steer of the linearized bicycle, component side: coordinates and speeds as inputs; accelerations and generalized forces"
  input Bicycle.Units.Angle phi "Roll angle phi of the rear frame, positive leaning right";
  input Bicycle.Units.Angle delta "Steer angle delta, positive steering right";
  input Bicycle.Units.AngularVelocity phi_dot "Roll rate der(phi)";
  input Bicycle.Units.AngularVelocity delta_dot "Steer rate der(delta)";
  Real phi_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Roll acceleration der(phi_dot)";
  Real delta_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Steer acceleration der(delta_dot)";
  flow Bicycle.Units.Torque Q_phi "Generalized force on the roll coordinate, exerted on the component through the connector";
  flow Bicycle.Units.Torque Q_delta "Generalized force on the steer coordinate, exerted on the component through the connector";
  annotation(
    defaultComponentName = "frame",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 0}, fillColor = {0, 128, 128}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-40, -40}, {40, 40}}, lineColor = {0, 0, 0}, fillColor = {0, 128, 128}, fillPattern = FillPattern.Solid),
      Text(extent = {{-160, 90}, {40, 50}}, textString = "%name", textColor = {0, 0, 0})}),
    Documentation(info = "<html>
<p>The connector of a component that contributes to the equations of motion of the linearized
bicycle (a body, the applied torques). The generalized coordinates q = [phi; delta] and speeds
q' are known where the states are, so they come in as <em>inputs</em>, from the
<a href=\"modelica://Bicycle.Linear.RollSteer_b\">RollSteer_b</a> connector of
<a href=\"modelica://Bicycle.Linear.Coordinates\">Coordinates</a>. What is left is one acausal
pair per coordinate: the acceleration q'' (potential, the same for every component) and the
generalized force Q (flow, positive into the component, summed to zero over a connection set).</p>
<p>Q is the generalized force the rest of the bicycle exerts on the component through the
coordinates. A component is in d'Alembert equilibrium under Q and its own generalized active and
inertia forces, so a body delivers Q = M_i q'' + v C1_i q' + (g K0_i + v^2 K2_i) q, and the
applied torques deliver Q = -[T_phi; T_delta]. The flow sum over the connection set is then
Kane's equations of the whole bicycle, eq (24):</p>
<pre>  sum of Q = M q'' + v C1 q' + (g K0 + v^2 K2) q - [T_phi; T_delta] = 0</pre>
<p><b>Why this form.</b> A connector with the four kinematic variables as potentials would need
four flows to be balanced (Modelica Language Specification, section 9.3.1: as many flow scalars
as potential scalars), and the inertia M_i cannot be passed as a flow besides Q without breaking
that count. The specification's way for such connectors is to pass the variables that one
component determines causally, as an input here matched by an output of RollSteer_b, and to keep
only pairs of a potential and a flow acausal. With the inertia terms inside Q, every component
is balanced on its own: two equations for Q, and the accelerations come from the connection.</p>
</html>"));
end RollSteer_a;
