within Bicycle.Linear;
model Torques "Roll torque on the rear frame and steer torque between rear and front frame"
  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame, positive tending to lean right";
  Bicycle.Interfaces.RealInput T_delta(final quantity = "Torque", final unit = "N.m") "Steer torque T_delta between rear frame and front frame, positive tending to steer right";
  Bicycle.Linear.RollSteer_a frame "Roll and steer coordinates; the torques go out through it as generalized forces";
equation
  frame.Q_phi = -T_phi;
  frame.Q_delta = -T_delta;
  annotation(Documentation(info = "<html>
<p>The applied torques of eq (24): T_phi and T_delta are the generalized forces of the roll and steer
coordinates. The component has no inertia: the generalized force through its
<a href=\"modelica://Bicycle.Linear.RollSteer_a\">RollSteer_a</a> connector balances the torques
alone (flows positive into the component, hence delivered with a minus sign). It uses neither the
coordinates nor the accelerations of the connector.</p>
</html>"));
end Torques;
