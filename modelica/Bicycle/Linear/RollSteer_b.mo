within Bicycle.Linear;
connector RollSteer_b "Roll and steer of the linearized bicycle, coordinates side: coordinates and speeds as outputs; accelerations and generalized forces"
  output Bicycle.Units.Angle phi "Roll angle phi of the rear frame, positive leaning right";
  output Bicycle.Units.Angle delta "Steer angle delta, positive steering right";
  output Bicycle.Units.AngularVelocity phi_dot "Roll rate der(phi)";
  output Bicycle.Units.AngularVelocity delta_dot "Steer rate der(delta)";
  Real phi_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Roll acceleration der(phi_dot)";
  Real delta_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Steer acceleration der(delta_dot)";
  flow Bicycle.Units.Torque Q_phi "Generalized force on the roll coordinate, exerted on the component through the connector";
  flow Bicycle.Units.Torque Q_delta "Generalized force on the steer coordinate, exerted on the component through the connector";
  annotation(
    defaultComponentName = "frame",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 128, 128}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid, lineThickness = 0.5)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Rectangle(extent = {{-40, -40}, {40, 40}}, lineColor = {0, 128, 128}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid, lineThickness = 0.5),
      Text(extent = {{-160, 90}, {40, 50}}, textString = "%name", textColor = {0, 0, 0})}),
    Documentation(info = "<html>
<p>The connector of <a href=\"modelica://Bicycle.Linear.Coordinates\">Coordinates</a>, the
component that holds the generalized coordinates q = [phi; delta] and speeds q' of the linearized
bicycle: it gives them as <em>outputs</em> to the
<a href=\"modelica://Bicycle.Linear.RollSteer_a\">RollSteer_a</a> connectors (inputs) of the bodies
and the torques. The accelerations q'' (potentials) and the generalized forces Q (flows, positive
into the component) are the same acausal pair as in RollSteer_a; the two connectors differ only in
the direction of the kinematics, as RealOutput and RealInput do. The connection of one RollSteer_b
with any number of RollSteer_a has one source for every input, and its flow sum determines q''.
See RollSteer_a for the meaning of Q and why the connector is built this way.</p>
</html>"));
end RollSteer_b;
