within Bicycle.Linear;
model Coordinates "Roll and steer coordinates of the linearized bicycle: solves the summed M q'' = Q for the accelerations"
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle phi (a state of the assembly)";
  Bicycle.Interfaces.RealInput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle delta (a state of the assembly)";
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate der(phi) (a state of the assembly)";
  Bicycle.Interfaces.RealInput delta_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Steer rate der(delta) (a state of the assembly)";
  Bicycle.Interfaces.RealOutput phi_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Roll acceleration der(phi_dot)";
  Bicycle.Interfaces.RealOutput delta_ddot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Steer acceleration der(delta_dot)";
  Bicycle.Linear.RollSteer frame "Roll and steer coordinates; receives the sums of the generalized inertias and forces";
equation
  frame.phi = phi;
  frame.delta = delta;
  frame.phi_dot = phi_dot;
  frame.delta_dot = delta_dot;
  // Linear in the accelerations: the compiler solves this 2x2 system.
  frame.M11*phi_ddot + frame.M12*delta_ddot = frame.Q_phi;
  frame.M12*phi_ddot + frame.M22*delta_ddot = frame.Q_delta;
  annotation(Documentation(info = "<html>
<p>The root of the connection set: it gives the bodies the coordinates and speeds and receives, by
the sum of the flows, the whole bicycle's mass matrix M and generalized force
Q = f - v C1 q' - (g K0 + v^2 K2) q. Kane's equations M q'' = Q give the accelerations.
The states stay in the assembly, so that they keep their names in an exported model.</p>
</html>"));
end Coordinates;
