within Bicycle.Mechanics.Joints;
model ActuatedRevolute "Revolute joint driven by a torque signal"
  extends Bicycle.Mechanics.Joints.PartialRevolute;
  Bicycle.Interfaces.RealInput tau_in(final quantity = "Torque", final unit = "N.m") "Torque on frame_b about the axis (reaction on frame_a)";
equation
  tau = tau_in;
  annotation(Documentation(info = "<html><p>A revolute joint with the torque <code>tau_in</code> between
its frames (see <code>PartialRevolute</code>).</p></html>"));
end ActuatedRevolute;
