within Bicycle.Linear;
connector RollSteer "Roll and steer of the linearized bicycle; flows: generalized inertia and generalized forces"
  Bicycle.Units.Angle phi "Roll angle phi of the rear frame, positive leaning right";
  Bicycle.Units.Angle delta "Steer angle delta, positive steering right";
  Bicycle.Units.AngularVelocity phi_dot "Roll rate der(phi)";
  Bicycle.Units.AngularVelocity delta_dot "Steer rate der(delta)";
  flow Bicycle.Units.MomentOfInertia M11 "Generalized inertia (mass matrix M), element (phi, phi)";
  flow Bicycle.Units.MomentOfInertia M12 "Generalized inertia (mass matrix M), element (phi, delta) = (delta, phi)";
  flow Bicycle.Units.MomentOfInertia M22 "Generalized inertia (mass matrix M), element (delta, delta)";
  flow Bicycle.Units.Torque Q_phi "Generalized force on the roll coordinate";
  flow Bicycle.Units.Torque Q_delta "Generalized force on the steer coordinate";
  annotation(Documentation(info = "<html>
<p>Generalized coordinates q = [phi; delta] and speeds q' of the linearized bicycle (potentials) and
what a component contributes to the equations of motion M q'' = Q (flows, summed over a connection
set, positive into the component). A body delivers its generalized inertia M_i (flows -M_i) and its
generalized force -(v C1_i q' + (g K0_i + v^2 K2_i) q) (flows of the opposite sign);
<a href=\"modelica://Bicycle.Linear.Coordinates\">Coordinates</a> receives the sums. The connector
is not balanced in the sense of Modelica 3 (4 potentials, 5 flows): like a multibody frame whose
accelerations are solved in one place, it is meant for the assemblies of this package.</p>
</html>"));
end RollSteer;
