within Bicycle.Linear;
model LinearizedRearFrame "Rear frame B (with the rigidly attached rider)"
  extends Bicycle.Icons.RearFrameIcon;
  extends Bicycle.Linear.PartialRearBody(final S = 0);
  parameter Bicycle.Units.MomentOfInertia Iyy(min = 0) "Inertia-tensor element yy about the centre of mass (does not enter the linear model)";
  annotation(Documentation(info = "<html>
<p>Rear frame with the rider sitting rigidly on it (hands off the handlebar): mass m, centre of
mass (x, z), inertia-tensor elements Ixx, Ixz, Izz about the centre of mass.</p>
</html>"));
end LinearizedRearFrame;
