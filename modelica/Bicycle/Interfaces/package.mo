within Bicycle;
package Interfaces "Connectors between bicycle components"
end Interfaces;
