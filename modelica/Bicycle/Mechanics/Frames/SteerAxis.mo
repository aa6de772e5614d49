within Bicycle.Mechanics.Frames;
model SteerAxis "Steer axis: revolute joint tilted back by lam from the frame's z axis, driven by the steer torque"
  extends Bicycle.Icons.SteerAxisIcon;
  extends Bicycle.Mechanics.Joints.ActuatedRevolute(final nx = sin(lam), final ny = 0, final nz = cos(lam)) annotation(IconMap(primitivesVisible = false));
  parameter Bicycle.Units.Angle lam "Steer-axis tilt lam from the vertical (pi/2 - head angle)";
  annotation(Documentation(info = "<html><p>The steer axis has the direction <code>(sin lam, 0, cos lam)</code>
in the rear frame's axes (down and forward). The steer angle is positive to the right, the steer
torque <code>tau_in</code> acts on the front frame (reaction on the rear frame).</p></html>"));
end SteerAxis;
