within Bicycle.Linear;
model Coordinates "Roll and steer coordinates of the linearized bicycle: gives the components q and q', returns the accelerations q'' that the summed generalized forces determine"
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle phi (a state of the assembly)";
  Bicycle.Interfaces.RealInput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle delta (a state of the assembly)";
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate der(phi) (a state of the assembly)";
  Bicycle.Interfaces.RealInput delta_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Steer rate der(delta) (a state of the assembly)";
  Bicycle.Interfaces.RealOutput phi_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Roll acceleration der(phi_dot)";
  Bicycle.Interfaces.RealOutput delta_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Steer acceleration der(delta_dot)";
  Bicycle.Linear.RollSteer_b frame "Roll and steer coordinates; the components' generalized forces meet here";
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
  annotation(Documentation(info = "<html>
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
